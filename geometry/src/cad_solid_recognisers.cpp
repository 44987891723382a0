// The one list of CAD solid recognisers (cad_solid_recognisers.hpp). It is explicit, not filled
// by self-registration from static initialisers: the geometry library is static, and the linker
// would drop a recogniser file that nothing names (docs/architecture.md, "Extension points").
// The order is part of the result: several recognisers accept some solids and build different
// patches (the box of examples/cad is a hexahedron, a prism of any face and an orthogonal block:
// tests/geometry/test_cad_solid_recognisers.cpp), so the specific ones with few exact patches
// come first (hexahedron: one volume; revolution: four exact rational quarters, and a solid of
// revolution it fails on ends the walk with its own reason), then the prism of an already cut
// face, and the general block split last. Appending keeps what existing parts become.
#include "cad_solid_recognisers.hpp"

#include <algorithm>

namespace isospring::geometry::detail {

SolidRecognition recognise_hexahedron(const SolidContext& context);  // cad_hexahedron.cpp
SolidRecognition recognise_revolution(const SolidContext& context);  // cad_revolution.cpp
SolidRecognition recognise_prism(const SolidContext& context);       // cad_prism.cpp
SolidRecognition recognise_block(const SolidContext& context);       // cad_block.cpp

std::vector<nurbs::Patch> model_face_patches(const CadModel& model, int f) {
  std::vector<nurbs::Patch> patches;
  for (size_t p = 0; p < model.face_patches.size(); ++p)
    if (model.patch_face[p] == f) patches.push_back(model.face_patches[p]);
  for (size_t p = 0; p < model.split_patches.size(); ++p)
    if (model.split_patch_face[p] == f) patches.push_back(model.split_patches[p]);
  return patches;
}

SolidContext solid_context(const TopoDS_Shape& solid, double volume, const CadModel& model,
                           const TopTools_IndexedMapOfShape& faces) {
  return SolidContext{
      solid, volume,
      [&model, &faces](const TopoDS_Shape& face) -> const nurbs::Patch* {
        const int f = faces.FindIndex(face) - 1;
        if (f < 0 || !model.face_reports[static_cast<size_t>(f)].natural) return nullptr;
        const auto it = std::find(model.patch_face.begin(), model.patch_face.end(), f);
        return &model.face_patches[static_cast<size_t>(it - model.patch_face.begin())];
      },
      [&model, &faces](const TopoDS_Face& face) {
        return model_face_patches(model, faces.FindIndex(face) - 1);
      }};
}

const std::vector<SolidRecogniser>& solid_recognisers() {
  static const std::vector<SolidRecogniser> list{
      {"hexahedron", recognise_hexahedron},
      {"revolution", recognise_revolution},
      {"prism", recognise_prism},
      {"block", recognise_block},
  };
  return list;
}

}  // namespace isospring::geometry::detail
