#pragma once
// Missing input files raise Python's FileNotFoundError, with the message the
// CLI prints for them.
#include <pybind11/pybind11.h>

#include <filesystem>
#include <string>

#include "core/error.h"

namespace acpca::python {

namespace py = pybind11;

/// adaptive_cpca.MissingFileError: both the module's Error (a ValueError) and
/// FileNotFoundError, so either `except` catches it. Set when the module loads.
inline PyObject*& missingFileErrorType() {
  static PyObject* type = PyExc_FileNotFoundError;
  return type;
}

/// Runs `read`, which opens `path`; when that fails because there is no such
/// file, the library's message (the CLI's words) is raised as MissingFileError.
template <typename Read>
auto openingFile(const std::string& path, Read&& read) {
  try {
    return read();
  } catch (const UserError& e) {
    std::error_code ec;
    if (!path.empty() && !std::filesystem::exists(path, ec)) {
      PyErr_SetString(missingFileErrorType(), e.what());
      throw py::error_already_set();
    }
    throw;
  }
}

}  // namespace acpca::python
