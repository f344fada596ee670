// The Python module `adaptive_cpca`: relighting from numpy over the C++
// libraries (not the CLI). Thin: argument conversion, the GIL released around
// the work, library errors raised as adaptive_cpca.Error. Its parts register
// themselves (python/module_parts.h).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/error.h"
#include "core/version.h"
#include "core/warning.h"
#include "dataset/file_info.h"
#include "python/long_calls.h"
#include "python/module_parts.h"
#include "python/opening_file.h"
#include "python/to_python.h"

PYBIND11_MODULE(_core, m) {
  using namespace acpca;
  using namespace acpca::python;
  m.attr("__version__") = kVersion;
  m.doc() =
      "Relight fixed-view images from adaptive-cpca transport and model files, into numpy "
      "arrays (H x W x 3 float32, linear).";
  static py::exception<UserError> error(m, "Error", PyExc_ValueError);
  {
    py::tuple bases = py::make_tuple(error, py::handle(PyExc_FileNotFoundError));
    PyObject* missing = PyErr_NewException("adaptive_cpca.MissingFileError", bases.ptr(), nullptr);
    if (!missing) throw py::error_already_set();
    m.add_object("MissingFileError", py::handle(missing));
    missingFileErrorType() = missing;
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const UserError& e) {
      error(e.what());
    }
  });

  // The libraries' warnings (a map's clamped negative texels, a missing
  // texture) become Python warnings, from whichever thread reports them.
  setWarningHandler([](const std::string& message) {
    py::gil_scoped_acquire gil;
    if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) < 0) PyErr_Clear();
  });

  m.def(
      "info",
      [](const std::string& path) {
        return openingFile(path, [&] { return toPython(describeFile(path).json); });
      },
      py::arg("path"), "What a transport or model file holds (as `info --json`).");
  registerFiles(m);
  registerShared(m);

  registerEnvironments(m);
  registerLights(m);
  registerRelighter(m);

  registerLongCalls(m);
}
