// The one list of CAD face recognisers (cad_face_recognisers.hpp), explicit for the same reason
// as the solids' (cad_solid_recognisers.cpp). The order is part of the result: a face that covers
// its whole parameter rectangle is used as it is (exact, no construction); a trimmed face of one
// wire and four edges becomes the Coons patch of its edges; any other planar face is cut into
// conforming four-sided patches. Appending keeps what existing parts become.
#include "cad_face_recognisers.hpp"

namespace isospring::geometry::detail {

FaceRecognition recognise_natural_face(const TopoDS_Face&, CadFace&);     // cad_natural_face.cpp
FaceRecognition recognise_coons_face(const TopoDS_Face&, CadFace&);       // cad_coons.cpp
FaceRecognition recognise_planar_cut_face(const TopoDS_Face&, CadFace&);  // cad_planar_face.cpp

const std::vector<FaceRecogniser>& face_recognisers() {
  static const std::vector<FaceRecogniser> list{
      {"natural", recognise_natural_face},
      {"coons", recognise_coons_face},
      {"planar_cut", recognise_planar_cut_face},
  };
  return list;
}

}  // namespace isospring::geometry::detail
