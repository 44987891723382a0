// The Python module `isospring` (docs/library.md). The library's
// InputError (bad files, fields, values) becomes isospring.InputError, a ValueError, with the same
// message the program prints.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "isospring/nurbs/error.hpp"

PYBIND11_MODULE(isospring, m) {
  m.doc() =
      "isospring: NURBS patches, exact refinement, isogeometric linear elasticity and "
      "NURBS mass-spring calibration.";
  m.attr("__version__") = ISOSPRING_VERSION;
  pybind11::register_exception<isospring::nurbs::InputError>(m, "InputError", PyExc_ValueError);
  isospring::python::bind_nurbs(m);
  isospring::python::bind_io(m);
  isospring::python::bind_analysis(m);
  isospring::python::bind_fitting(m);
  isospring::python::bind_identify(m);
  isospring::python::bind_immersed(m);
  isospring::python::bind_runtime(m);
}
