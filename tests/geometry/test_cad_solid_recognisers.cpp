// The list of CAD solid recognisers (geometry/src/cad_solid_recognisers.hpp): its order, why
// the order matters (a box is accepted by three recognisers), and read_cad builds every
// committed part with the first recogniser of the list that accepts it.
#include <gtest/gtest.h>

#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <map>

#include "../../geometry/src/cad_reader.hpp"
#include "../../geometry/src/cad_solid_recognisers.hpp"
#include "isospring/geometry/cad.hpp"

namespace isospring::geometry {
namespace {

std::filesystem::path part(const std::string& name) {
  return std::filesystem::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad" / name;
}

// Which recognisers accept the file's first solid, given the faces read_cad made of it.
struct Outcome {
  std::vector<std::string> accepted;                    // in list order
  std::map<std::string, detail::SolidRecognition> all;  // by name
  CadModel model;
};

Outcome recognise(const std::filesystem::path& file) {
  Outcome out;
  out.model = read_cad(file);
  std::string unit;
  const TopoDS_Shape shape = detail::read_cad_shape(file, unit);
  TopTools_IndexedMapOfShape solids, faces;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  GProp_GProps props;
  BRepGProp::VolumeProperties(solids(1), props, 1e-9);
  const detail::SolidContext context =
      detail::solid_context(solids(1), props.Mass(), out.model, faces);
  for (const detail::SolidRecogniser& r : detail::solid_recognisers()) {
    out.all[r.name] = r.recognise(context);
    if (out.all[r.name].recognised) out.accepted.push_back(r.name);
  }
  return out;
}

bool same_patches(const std::vector<nurbs::Patch>& a, const std::vector<nurbs::Patch>& b) {
  if (a.size() != b.size()) return false;
  for (size_t p = 0; p < a.size(); ++p) {
    if (a[p].control_points() != b[p].control_points() || a[p].weights() != b[p].weights() ||
        a[p].param_dim() != b[p].param_dim())
      return false;
    for (int d = 0; d < a[p].param_dim(); ++d)
      if (a[p].all_knots()[static_cast<size_t>(d)].values() !=
          b[p].all_knots()[static_cast<size_t>(d)].values())
        return false;
  }
  return true;
}

TEST(CadSolidRecognisers, TheListAndItsOrder) {
  std::vector<std::string> names;
  for (const detail::SolidRecogniser& r : detail::solid_recognisers()) names.push_back(r.name);
  EXPECT_EQ(names, (std::vector<std::string>{"hexahedron", "revolution", "prism", "block"}));
}

// Why the list is ordered: the block is a hexahedron, the prism of any of its faces and an
// orthogonal block; the first (one trilinear volume) is what read_cad keeps.
TEST(CadSolidRecognisers, ABoxIsAcceptedByThreeAndTheFirstWins) {
  const Outcome box = recognise(part("block.step"));
  EXPECT_EQ(box.accepted, (std::vector<std::string>{"hexahedron", "prism", "block"}));
  EXPECT_TRUE(same_patches(box.model.volume_patches, box.all.at("hexahedron").patches));
  EXPECT_EQ(box.model.solid_notes, std::vector<std::string>{""});
}

// Every recogniser builds a committed part, and read_cad keeps the first one's patches.
TEST(CadSolidRecognisers, EveryRecogniserBuildsACommittedPart) {
  const std::map<std::string, std::string> first{{"block.step", "hexahedron"},
                                                 {"tube.step", "revolution"},
                                                 {"plate_with_holes.step", "prism"},
                                                 {"bracket.step", "block"}};
  std::vector<std::string> built;
  for (const auto& [file, kind] : first) {
    const Outcome o = recognise(part(file));
    ASSERT_FALSE(o.accepted.empty()) << file;
    EXPECT_EQ(o.accepted.front(), kind) << file;
    EXPECT_TRUE(same_patches(o.model.volume_patches, o.all.at(kind).patches)) << file;
    EXPECT_EQ(o.model.solid_remarks[0], o.all.at(kind).remark) << file;
    built.push_back(o.accepted.front());
  }
  for (const detail::SolidRecogniser& r : detail::solid_recognisers())
    EXPECT_NE(std::find(built.begin(), built.end(), r.name), built.end()) << r.name;
}

}  // namespace
}  // namespace isospring::geometry
