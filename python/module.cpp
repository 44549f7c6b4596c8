// The module definition of fibrane._core: the binding files' parts, the translation of fibrane's
// InputError into the Python exception fibrane.InputError, and glibc's malloc thresholds of the CLI.
#include <malloc.h>

#include <climits>
#include <cstdlib>

#include "bindings.hpp"
#include "common/error.hpp"

namespace {

// The CLI gives glibc's malloc these thresholds through GLIBC_TUNABLES (run/process_environment.cpp says
// why: the factorisation's and assembly's work arrays stay mapped between Newton iterations); a Python
// process has started before the module loads, so they are set here, unless the user set the tunables.
void keep_large_blocks() {
  if (std::getenv("GLIBC_TUNABLES")) return;
  // mallopt takes an int: 2 GiB - 1 for both thresholds, where the CLI's tunables give 32 GiB and 16 GiB,
  // so blocks above 2 GiB (the factor of the membrane at 1.1 M unknowns is 5 GB) are still mapped afresh
  // from Python; one arena as the CLI's.
  mallopt(M_MMAP_THRESHOLD, INT_MAX);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
  mallopt(M_ARENA_MAX, 1);  // for the threads started after this (OpenMP's, on the first parallel region)
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "fibrane's C++ core; use the package fibrane (docs/python.md)";
  m.attr("version") = FIBRANE_VERSION;
  keep_large_blocks();
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const fibrane::InputError& e) {
      pybind11::object cls = pybind11::module_::import("fibrane.errors").attr("InputError");
      pybind11::object error = cls(e.what());
      PyErr_SetObject(cls.ptr(), error.ptr());
    }
  });
  fibrane::python::bind_case(m);
  fibrane::python::bind_run(m);
  fibrane::python::bind_results(m);
  fibrane::python::bind_laws(m);
}
