// isospring.RuntimeModel: the engine runtime (runtime/include/isospring/runtime/runtime.h) from
// Python, numpy arrays in and out. Load errors are isospring.InputError with the runtime's
// message (file and field).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "bindings.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/runtime/runtime.h"

namespace isospring::python {
namespace {

namespace py = pybind11;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

class RuntimeModel {
 public:
  explicit RuntimeModel(const std::string& path) {
    char error[2000] = "";
    model_.reset(isospring_model_load(path.c_str(), error, sizeof(error)));
    if (!model_) throw nurbs::InputError(error);
  }

  isospring_model* get() const { return model_.get(); }
  size_t size() const { return isospring_model_state_size(get()); }

  // A flat state vector of the model's size (any shape with that many entries), or null.
  const double* state(const py::object& value, Array& keep, const char* name) const {
    if (value.is_none()) return nullptr;
    keep = Array::ensure(value);
    if (!keep || static_cast<size_t>(keep.size()) != size())
      throw nurbs::InputError(std::string(name) + ": expected " + std::to_string(size()) +
                              " numbers (the model's state size)");
    return keep.data();
  }

  Array vector(size_t n) const { return Array(static_cast<py::ssize_t>(n)); }

 private:
  std::unique_ptr<isospring_model, void (*)(isospring_model*)> model_{nullptr,
                                                                      isospring_model_free};
};

py::tuple forces(const RuntimeModel& m, const py::object& x, const py::object& v) {
  Array kx, kv;
  const double* px = m.state(x, kx, "x");
  if (!px) throw nurbs::InputError("x: the positions are required");
  const double* pv = m.state(v, kv, "v");
  Array f = m.vector(m.size());
  const double energy = isospring_model_forces(m.get(), px, pv, f.mutable_data());
  return py::make_tuple(f, energy);
}

Array force_jvp(const RuntimeModel& m, const py::object& x, const py::object& dx,
                const py::object& v, const py::object& dv) {
  Array kx, kdx, kv, kdv;
  const double* px = m.state(x, kx, "x");
  if (!px) throw nurbs::InputError("x: the positions are required");
  Array df = m.vector(m.size());
  isospring_model_force_jvp(m.get(), px, m.state(v, kv, "v"), m.state(dx, kdx, "dx"),
                            m.state(dv, kdv, "dv"), df.mutable_data());
  return df;
}

}  // namespace

void bind_runtime(py::module_& m) {
  for (auto [name, value] : {std::pair{"TERM_SPRINGS", ISOSPRING_TERM_SPRINGS},
                             std::pair{"TERM_CELL_VOLUME", ISOSPRING_TERM_CELL_VOLUME},
                             std::pair{"TERM_CELL_SHEAR", ISOSPRING_TERM_CELL_SHEAR},
                             std::pair{"TERM_POINT_VOLUME", ISOSPRING_TERM_POINT_VOLUME},
                             std::pair{"TERM_POINT_SHEAR", ISOSPRING_TERM_POINT_SHEAR},
                             std::pair{"TERM_REDUCED", ISOSPRING_TERM_REDUCED},
                             std::pair{"TERM_ALL", ISOSPRING_TERM_ALL}})
    m.attr(name) = py::int_(static_cast<int>(value));
  py::class_<RuntimeModel>(m, "RuntimeModel",
                           "A calibrated model (model.json or a reduced model) loaded by the "
                           "engine runtime: forces and Jacobian-vector products per step.")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def_property_readonly("reduced",
                             [](const RuntimeModel& r) {
                               return isospring_model_kind(r.get()) == ISOSPRING_MODEL_REDUCED;
                             })
      .def_property_readonly(
          "dimension", [](const RuntimeModel& r) { return isospring_model_dimension(r.get()); })
      .def_property_readonly(
          "particles",
          [](const RuntimeModel& r) { return isospring_model_particle_count(r.get()); })
      .def_property_readonly("state_size", &RuntimeModel::size)
      .def_property_readonly(
          "rest_positions",
          [](const RuntimeModel& r) {
            const size_t n = isospring_model_particle_count(r.get());
            const auto d = static_cast<size_t>(isospring_model_dimension(r.get()));
            Array out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(d)});
            std::copy_n(isospring_model_rest_positions(r.get()), n * d, out.mutable_data());
            return out;
          })
      .def(
          "term_count",
          [](const RuntimeModel& r, int term) { return isospring_model_term_count(r.get(), term); },
          py::arg("term"))
      .def_property(
          "terms", [](const RuntimeModel& r) { return isospring_model_terms(r.get()); },
          [](RuntimeModel& r, int mask) { isospring_model_set_terms(r.get(), mask); },
          "Mask of the TERM_* kinds the evaluations include (all by default).")
      .def("forces", &forces, py::arg("x"), py::arg("v") = py::none(),
           "(f, energy): -dE/dx at the flat state x plus the damping forces at v (None: none).")
      .def("force_jvp", &force_jvp, py::arg("x"), py::arg("dx"), py::arg("v") = py::none(),
           py::arg("dv") = py::none(), "(df/dx) dx + (df/dv) dv at (x, v).");
}

}  // namespace isospring::python
