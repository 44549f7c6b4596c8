#pragma once
// Parallel VTK output (case key output.vtk_pieces), beside the gathered files of RunOutput: at every step
// that writes VTK, each process writes its piece of every series, a contiguous range of the series' cells
// (io/pvtu.hpp), as vtk/<series>_<step>_<rank>.vtu, and the first process the .pvtu naming the pieces
// (vtk/<series>_<step>.pvtu) and the series of those, <series>_pieces.pvd. Every file is written
// atomically and listed in the run's manifest before it is created (the first process lists the other
// processes' pieces, then the processes write). A serial run writes one piece per series.
#include <memory>
#include <string>
#include <vector>

#include "case/case.hpp"
#include "io/vtk.hpp"
#include "output/run_output.hpp"

namespace fibrane::output {

// One process's share of the parallel VTK output: every process of a run holds one and calls write()
// at the same steps (collective in a distributed run).
class VtkPieces {
 public:
  // `first`: the first process's RunOutput (whose manifest lists the files), null on the other processes.
  // `resume` (a restart): the gathered series' position, whose steps the pieces' series continue.
  VtkPieces(const casefile::Case& c, std::string directory, const model::Model& m, RunOutput* first,
            const OutputPosition* resume);
  // Writes this process's pieces of the model's state at `report`'s step; the first process the .pvtu
  // files and the series. std::runtime_error on every process if any failed.
  void write(const model::Model& m, const solve::StepReport& report);

 private:
  const casefile::Case& case_;
  std::string dir_;
  RunOutput* first_;
  int rank_ = 0, size_ = 1;
  std::vector<io::PvdCollection> series_;  // the first process's <series>_pieces.pvd, in RunOutput's order
};

}  // namespace fibrane::output
