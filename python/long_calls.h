#pragma once
// The module's long calls: precompute and compress.
#include <pybind11/pybind11.h>

namespace acpca::python {

void registerLongCalls(pybind11::module_& m);

}  // namespace acpca::python
