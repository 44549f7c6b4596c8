// steps.out_of_core's forms: true or a directory (every factorisation out of core), when_needed or
// {when: needed, directory: D} (in memory where a factorisation fits, in files where not), false. The
// in-memory path keeps CHOLMOD's split LL^T, and the case's memory estimate names the path.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

std::string plate_case(const std::string& steps) {
  return "shells:\n  - name: plate\n    geometry: {rectangle: {origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}}\n"
         "    refine: {degree: 2, elements: [2, 2]}\n    thickness: 0.1\n    material: {young: 1000, poisson: 0.3}\n"
         "constraints:\n  - {body: plate, at: {edge: v0}, fix: [x, y, z]}\nsteps: {dt: 0.5" + steps + "}\n";
}

std::string temporary_directory() {
  const char* tmp = std::getenv("TMPDIR");
  return tmp && *tmp ? tmp : "/tmp";
}

TEST(OutOfCoreKey, ReadsEachForm) {
  const std::string dir = fresh_directory("out-of-core-key-files").string();
  struct Form {
    std::string steps, directory;
    bool when_needed;
  };
  for (const Form& f : {Form{", out_of_core: when_needed, split: true", temporary_directory(), true},
                        Form{", out_of_core: {when: needed, directory: " + dir + "}", dir, true},
                        Form{", out_of_core: {directory: " + dir + "}", dir, false},
                        Form{", out_of_core: {when: always}", temporary_directory(), false},
                        Form{", out_of_core: " + dir, dir, false}, Form{", out_of_core: true", temporary_directory(), false},
                        Form{", out_of_core: false", "", false}, Form{"", "", false}}) {
    const casefile::Case c = read_yaml("out-of-core-key", plate_case(f.steps));
    const solve::LinearSolverSettings& ls = c.run.linear_solver;
    EXPECT_EQ(ls.out_of_core_directory, f.directory) << f.steps;
    EXPECT_EQ(ls.out_of_core_when_needed, f.when_needed) << f.steps;
    const std::string& path = c.memory_estimate.path;
    EXPECT_EQ(path.find("where a factorisation does not fit") != std::string::npos, f.when_needed) << path;
    EXPECT_EQ(path.find("out of core") != std::string::npos, !f.directory.empty()) << path;
  }
  EXPECT_TRUE(read_yaml("out-of-core-key", plate_case(", out_of_core: when_needed, split: true")).run.linear_solver.split);
}

}  // namespace
}  // namespace fibrane::testing
