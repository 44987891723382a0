#pragma once
// CAD parts in and out through OpenCascade 7.6: STEP (.step/.stp) and IGES (.iges/.igs).
//
// Import converts every face to NURBS (BRepBuilderAPI_NurbsConvert), in metres whatever unit the
// file declares. A face becomes a patch when it is a whole (untrimmed) parameter rectangle of its
// surface ("natural boundary"); periodic surfaces are made clamped. A trimmed face with one wire of
// four edges becomes the Coons patch of its edges (exact B-spline conversions of the edge curves,
// made compatible; see coons.hpp) when that patch lies on the face's surface (e.g. planar
// quadrilaterals, cylinder faces between two lines and two conic arcs). Faces are oriented so
// that dX/du x dX/dv points out of the solid. A planar trimmed face with holes or another number
// of edges (plates with holes, L-shapes, disks) is cut into conforming 4-sided patches whose
// boundaries are its exact edge curves plus straight cut lines (planar_split.hpp: a ring of four
// patches around every hole, rectangles elsewhere), accepted when every Jacobian is positive and
// the area matches OpenCascade's to 1e-9. Other trimmed faces (curved faces with holes, outlines
// with slanted edges around holes, curved 4-sided faces whose interior is not the blend of their
// edges) are reported with what to do. Trimmed (immersed) analysis is not done. A
// solid of hexahedral topology (six 4-sided faces, each the Coons patch of its edges) becomes one
// volume patch by trivariate transfinite interpolation (coons_volume; exact trilinear for planar
// blocks); a hexahedral prism whose base is a natural face (e.g. a bumped spline face) becomes the
// exact extrusion of that face; a full solid of revolution with a 4-sided profile (a tube, a
// revolved trapezoid, a solid cylinder whose profile closes along the axis, a solid torus whose
// circular section is cut into four arcs) becomes four exact rational 90-degree volume patches.
// A prism of a planar face (every other face a side wall along its normal or the far cap: plates
// with through-holes, extruded L sections) becomes the face's patches extruded, its volume
// matched to OpenCascade's to 1e-9. Planar faces can also be extruded along their normal into
// volumes. Not handled (reported per solid): other solids (e.g. an L section with holes across
// its legs, solids of revolution whose profile is not 4-sided such as balls and cones).
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

struct CadFace {
  int index = 0;             // 0-based, in TopExp_Explorer order
  std::string surface_type;  // plane, cylinder, cone, sphere, torus, bspline, revolution, ...
  int wires = 0;
  int edges = 0;
  double area = 0.0;             // of the trimmed face (OCCT, m^2)
  double perimeter = 0.0;        // total length of its edges (OCCT, m)
  bool natural = false;          // a whole parameter rectangle: usable as a patch
  bool coons = false;            // trimmed, 4 edges: usable as the Coons patch of its edges
  double coons_deviation = 0.0;  // largest distance of that patch from the CAD surface (m)
  /// > 0: a planar trimmed face (holes, other than 4 edges) cut into this many conforming
  /// 4-sided patches (planar_split.hpp), with the sampled Jacobian bounds of those patches
  /// (dX/du x dX/dv along the outward normal, m^2 per unit parameter area).
  int split = 0;
  double jacobian_min = 0.0, jacobian_max = 0.0;
  std::string note;  // why not usable and what to do
};

struct CadModel {
  std::filesystem::path file;
  std::string file_unit;  // as declared by the file (e.g. "MM", "M", "INCH")
  int solids = 0, shells = 0, faces = 0, edges = 0;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  double volume = 0.0;  // of the closed solids (OCCT, m^3); 0 without solids
  double area = 0.0;    // of all faces (OCCT, m^2)
  std::vector<CadFace> face_reports;
  std::vector<nurbs::Patch> face_patches;   // one per usable face (natural or Coons), in face order
  std::vector<int> patch_face;              // face index of each face patch
  std::vector<nurbs::Patch> split_patches;  // the patches of the cut faces (CadFace::split)
  std::vector<int> split_patch_face;        // face index of each of them
  std::vector<nurbs::Patch> volume_patches;  // solids as volumes (1 per block, 4 per revolution,
                                             // the extruded cut of the base face per prism)
  std::vector<int> patch_solid;              // solid index (0-based) of each volume patch
  std::vector<std::string> solid_notes;      // per solid: empty if a volume patch, else why not
  std::vector<std::string> solid_remarks;    // per solid: what a user should know about its
                                             // volume patches (empty: nothing)
  /// What the reader skipped without harm to the shape, e.g. STEP entities outside the geometry
  /// (styles, validation properties) that OpenCascade cannot read, when the shape transferred and
  /// passed OpenCascade's validity check (BRepCheck_Analyzer).
  std::vector<std::string> warnings;
};

/// Reads a STEP or IGES file (by extension, case-insensitive). Throws nurbs::InputError naming the
/// file when it is missing, empty, not STEP/IGES, unreadable or has no geometry. STEP entities
/// OpenCascade cannot read are an error when they belong to the geometry (or the shape does not
/// transfer or is invalid), otherwise a warning in CadModel::warnings.
CadModel read_cad(const std::filesystem::path& file);

/// Human-readable report: unit, counts, bounding box, volume/area and one line per face.
std::string describe(const CadModel& model);

/// The patches an analysis uses: the volume patches when every solid became volume patches
/// (hexahedral, prism or revolution; solid_notes all empty), otherwise the face patches;
/// `thickness` > 0 extrudes planar faces along their normal (inwards for a solid's faces is not
/// assumed: along +normal). Without thickness, faces in the plane z = 0 come right-handed in x-y
/// (u reversed on faces facing -z), ready for a 2D analysis. Throws InputError (naming the file,
/// the face and what to do) when a requested face cannot be used.
std::vector<nurbs::Patch> cad_patches(const CadModel& model, double thickness = 0.0,
                                      const std::vector<int>& faces = {});

/// The volume patches of the chosen solids (0-based, in file order), e.g. one body of a
/// multi-body part. Throws InputError naming the file and the solid when an index is out of range
/// or a chosen solid did not become volume patches (with the reason, from solid_notes).
std::vector<nurbs::Patch> cad_solid_patches(const CadModel& model, const std::vector<int>& solids);

/// What write_cad wrote.
struct CadWriteSummary {
  int faces = 0;   // B-spline faces, those of the solids included
  int solids = 0;  // volume patches written as closed solids
  /// Per volume patch that could not be closed (OpenCascade's sewing left free edges, e.g. a
  /// collapsed side): why; its faces are then written as a separate open shell.
  std::vector<std::string> notes;
};

/// Writes patches to STEP or IGES (by extension), in metres: surfaces as B-spline faces, every
/// volume as a closed solid (its six boundary faces sewn into one shell with shared edges and
/// outward normals: STEP MANIFOLD_SOLID_BREP, IGES manifold solid B-rep object, type 186).
/// Throws nurbs::InputError for an unknown extension, std::runtime_error when OpenCascade fails.
CadWriteSummary write_cad(const std::filesystem::path& file,
                          const std::vector<nurbs::Patch>& patches);

/// Side `end` (0 = min, 1 = max) of direction `dir` of a surface or volume patch as a patch of one
/// dimension less (its control points and knots).
nurbs::Patch boundary_side(const nurbs::Patch& patch, int dir, int end);

}  // namespace isospring::geometry
