// The exact face surfaces of the last update of a vtkWireFurCADReader, for programs that open
// the CAD module at run time (the wirefur command grows fur on them): each meshed face as the
// core's surface concept (wfcad::FaceSurface) and the face's trimming as a 0 / 1 mask over its
// unit (s, t) square, usable as fur's density map, so hairs grow only on the face itself. No
// OpenCASCADE types here. Not wrapped.
#pragma once

#include "surface/surface.h"
#include "texture/texture.h"

#include <memory>
#include <vector>

class vtkWireFurCADReader;

struct WireFurCadFace {
  std::shared_ptr<const wf::Surface> surface;      ///< S, Su, Sv from the face's own surface
  std::shared_ptr<const wf::ScalarTexture> inside; ///< 1 on the face, 0 where it is trimmed away
  int faceId = 0;                                  ///< as in the reader's FaceId array
  int part = 0;                                    ///< as in the reader's PartId array
};

/// Fills `faces` with the meshed faces of the reader's last update (in FaceId order); returns
/// the count. The surfaces stay valid after the reader is gone.
using WireFurCadFacesFunction = int (*)(vtkWireFurCADReader* reader, std::vector<WireFurCadFace>* faces);
extern "C" int wirefur_cad_face_surfaces(vtkWireFurCADReader* reader, std::vector<WireFurCadFace>* faces);
