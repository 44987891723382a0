#pragma once
// One function per library module adds its part of the Python module `isospring` (module.cpp).
#include <pybind11/pybind11.h>

namespace isospring::python {

void bind_nurbs(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_analysis(pybind11::module_& m);
void bind_fitting(pybind11::module_& m);
void bind_identify(pybind11::module_& m);
void bind_immersed(pybind11::module_& m);
void bind_runtime(pybind11::module_& m);

}  // namespace isospring::python
