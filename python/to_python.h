#pragma once
// Library JSON (file descriptions, run statistics) as plain Python objects.
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace acpca::python {

namespace py = pybind11;

inline py::object toPython(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

}  // namespace acpca::python
