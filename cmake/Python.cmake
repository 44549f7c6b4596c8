# The Python module (python/): needs the Python headers (python3-dev) and pybind11 (pybind11-dev), both
# installed by scripts/install-deps. Without them the module is left out with a message, and the rest of
# the build is unchanged. The interpreter is /usr/bin/python3 (Debian's, with numpy and pytest) unless
# Python_EXECUTABLE names another: an interpreter first on PATH (pyenv, a virtual environment) may lack them.
# Sanitizer builds leave it out too: an extension built with AddressSanitizer cannot load into an
# interpreter that is not (the ASan runtime must come first in the process).
if(FIBRANE_PYTHON AND FIBRANE_SANITIZE)
  message(STATUS "fibrane: the Python module is NOT built with FIBRANE_SANITIZE (the interpreter is not instrumented)")
  set(FIBRANE_PYTHON OFF)
endif()
if(FIBRANE_PYTHON)
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python 3.8 COMPONENTS Interpreter Development.Module)
  if(Python_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(NOT Python_FOUND OR NOT pybind11_FOUND)
    message(STATUS "fibrane: the Python module is NOT built: it needs python3-dev and pybind11-dev "
      "(scripts/install-deps installs them); Python found: ${Python_FOUND}, pybind11 found: ${pybind11_FOUND}")
    set(FIBRANE_PYTHON OFF)
  else()
    message(STATUS "fibrane: the Python module is built for ${Python_EXECUTABLE} (Python ${Python_VERSION}, "
      "pybind11 ${pybind11_VERSION})")
  endif()
endif()
