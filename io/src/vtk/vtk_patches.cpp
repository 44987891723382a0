#include "isospring/io/vtk_patches.hpp"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkHigherOrderHexahedron.h>
#include <vtkHigherOrderQuadrilateral.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <stdexcept>

#include "isospring/nurbs/bezier_extraction.hpp"
#include "vtk_internal.hpp"

namespace isospring::io {
namespace {
using Dims = std::array<int, 3>;

int flat(const Dims& n, int i, int j, int k) {
  return i + n[0] * (j + n[1] * k);
}

/// The extraction operators of a direction assembled into one (elements*p + 1) x n matrix: row
/// e*p + k holds the coefficients of Bezier point k of element e. Rows shared by neighbouring
/// elements agree because the extracted curve is continuous there.
Eigen::MatrixXd global_extraction(const nurbs::KnotVector& knots) {
  const std::vector<Eigen::MatrixXd> operators = nurbs::bezier_extraction(knots);
  const std::vector<int> spans = knots.element_spans();
  const int p = knots.degree();
  Eigen::MatrixXd m =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(operators.size()) * p + 1, knots.num_basis());
  for (size_t e = 0; e < operators.size(); ++e)
    for (int k = 0; k <= p; ++k)
      for (int a = 0; a <= p; ++a)
        m(static_cast<Eigen::Index>(e) * p + k, spans[e] - p + a) = operators[e](a, k);
  return m;
}

/// Applies `m` along direction `dir` of tensor-ordered rows (one row per point).
Eigen::MatrixXd apply_along(int dir, const Eigen::MatrixXd& m, Dims& n,
                            const Eigen::MatrixXd& data) {
  Dims out_n = n;
  out_n[static_cast<size_t>(dir)] = static_cast<int>(m.rows());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(out_n[0] * out_n[1] * out_n[2], data.cols());
  for (int k = 0; k < out_n[2]; ++k)
    for (int j = 0; j < out_n[1]; ++j)
      for (int i = 0; i < out_n[0]; ++i) {
        std::array<int, 3> ijk{i, j, k};
        const int row = ijk[static_cast<size_t>(dir)];
        const int target = flat(out_n, i, j, k);
        for (int a = 0; a < n[static_cast<size_t>(dir)]; ++a) {
          if (m(row, a) == 0.0) continue;
          ijk[static_cast<size_t>(dir)] = a;
          out.row(target) += m(row, a) * data.row(flat(n, ijk[0], ijk[1], ijk[2]));
        }
      }
  n = out_n;
  return out;
}

/// Position of local Bezier point (i, j, k) of a cell in VTK's higher-order point order
/// (vertices, edges, faces, interior).
int vtk_local_index(int param_dim, int i, int j, int k, const int* order) {
  if (param_dim == 1) return i == 0 ? 0 : (i == order[0] ? 1 : i + 1);
  if (param_dim == 2) return vtkHigherOrderQuadrilateral::PointIndexFromIJK(i, j, order);
  return vtkHigherOrderHexahedron::PointIndexFromIJK(i, j, k, order);
}
}  // namespace

void write_patches_bezier_vtu(const std::filesystem::path& path,
                              const std::vector<nurbs::Patch>& patches,
                              const std::vector<ControlField>& fields) {
  detail::check_control_fields(patches, fields);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->Allocate();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto weights = detail::make_double_array("RationalWeights", 1, 0);
  auto degrees = detail::make_double_array("HigherOrderDegrees", 3, 0);
  auto patch_ids = detail::make_int_array("patch", 0);
  std::vector<vtkSmartPointer<vtkDoubleArray>> field_arrays;
  for (const ControlField& f : fields)
    field_arrays.push_back(detail::make_double_array(f.name, f.components, 0));

  for (size_t p = 0; p < patches.size(); ++p) {
    const nurbs::Patch& patch = patches[p];
    const int dim = patch.param_dim();
    // Homogeneous channels (w x, w y, w z, w, w f...): extraction is linear in them, and the
    // rational field sum R_i f_i has Bezier coefficients (C^T (w f))_k / (C^T w)_k.
    int channels = 4;
    for (const ControlField& f : fields) channels += f.components;
    Eigen::MatrixXd data(patch.num_points(), channels);
    for (int a = 0; a < patch.num_points(); ++a) {
      const double w = patch.weight(a);
      data.block<1, 3>(a, 0) = w * patch.control_point(a).transpose();
      data(a, 3) = w;
      int column = 4;
      for (const ControlField& f : fields) {
        data.block(a, column, 1, f.components) = w * f.coefficients[p].col(a).transpose();
        column += f.components;
      }
    }
    Dims n{patch.num_points(0), patch.num_points(1), patch.num_points(2)};
    for (int d = 0; d < dim; ++d) data = apply_along(d, global_extraction(patch.knots(d)), n, data);

    const vtkIdType offset = points->GetNumberOfPoints();
    for (Eigen::Index b = 0; b < data.rows(); ++b) {
      const double w = data(b, 3);
      const Eigen::Vector3d x = data.block<1, 3>(b, 0).transpose() / w;
      points->InsertNextPoint(x.data());
      weights->InsertNextValue(w);
      int column = 4;
      for (size_t f = 0; f < fields.size(); ++f) {
        const Eigen::VectorXd value =
            data.block(b, column, 1, fields[f].components).transpose() / w;
        field_arrays[f]->InsertNextTuple(value.data());
        column += fields[f].components;
      }
    }

    int order[3] = {0, 0, 0};
    Dims elements{1, 1, 1};
    for (int d = 0; d < dim; ++d) {
      order[d] = patch.degree(d);
      elements[static_cast<size_t>(d)] = patch.knots(d).num_elements();
    }
    const int cell_type =
        dim == 1 ? VTK_BEZIER_CURVE : (dim == 2 ? VTK_BEZIER_QUADRILATERAL : VTK_BEZIER_HEXAHEDRON);
    const int local_count =
        (order[0] + 1) * (dim >= 2 ? order[1] + 1 : 1) * (dim >= 3 ? order[2] + 1 : 1);
    std::vector<vtkIdType> connectivity(static_cast<size_t>(local_count));
    for (int ek = 0; ek < elements[2]; ++ek)
      for (int ej = 0; ej < elements[1]; ++ej)
        for (int ei = 0; ei < elements[0]; ++ei) {
          for (int k = 0; k <= order[2]; ++k)
            for (int j = 0; j <= order[1]; ++j)
              for (int i = 0; i <= order[0]; ++i) {
                const int global = flat(n, ei * order[0] + i, ej * order[1] + j, ek * order[2] + k);
                connectivity[static_cast<size_t>(vtk_local_index(dim, i, j, k, order))] =
                    offset + global;
              }
          grid->InsertNextCell(cell_type, local_count, connectivity.data());
          const double cell_degrees[3] = {double(order[0]), double(order[1]), double(order[2])};
          degrees->InsertNextTuple(cell_degrees);
          patch_ids->InsertNextValue(static_cast<int>(p));
        }
  }
  grid->SetPoints(points);
  grid->GetPointData()->SetRationalWeights(weights);
  for (auto& a : field_arrays) grid->GetPointData()->AddArray(a);
  grid->GetCellData()->SetHigherOrderDegrees(degrees);
  grid->GetCellData()->AddArray(patch_ids);
  detail::write_xml_dataset(path, grid);
}

}  // namespace isospring::io
