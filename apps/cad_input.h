// CAD input for the wirefur command (.step .stp .iges .igs .brep .FCStd): read by the VTK
// module WireFur::CAD (vtkWireFurCADReader, OpenCASCADE), which this program opens at run time
// only when a CAD file is given, so that nothing else pays for loading OpenCASCADE (DESIGN.md:
// "load OpenCASCADE only for CAD input"). See docs/cad.md.
#pragma once

#include "mesh_io.h"
#include "scene_file.h"

#include "surface/surface.h"
#include "texture/texture.h"

#include <nlohmann/json.hpp>

#include <memory>

#include <string>
#include <vector>

namespace wfapp {

/// True for the CAD extensions (any case).
bool isCadFile(const std::string& path);

/// Consumes a CAD option at args[i] (advancing i past its value) and returns true, or returns
/// false when args[i] is not one. Throws UsageError for a bad value.
bool parseCadOption(const std::vector<std::string>& args, size_t& i, CadOptions& options);

/// One face of a CAD file as the core's surface concept, with its trimming as a 0 / 1 mask over
/// the face's unit (s, t) square (growth's density map), so generators grow on the face only.
struct CadFaceSurface {
  std::shared_ptr<const wf::Surface> surface;
  std::shared_ptr<const wf::ScalarTexture> inside;
  int faceId = 0, part = 0;
};

/// What a CAD file gives: the faces as one mesh with exact (u, v), Su, Sv and normals and the
/// file's colours; the edges (lines) and iso lines as polylines; per-triangle part index.
struct CadGeometry {
  LoadedGeometry geometry;             ///< mesh: all faces; lines: the edges
  wf::PolylineSet isoLines;
  std::vector<std::string> partNames;
  std::vector<int> trianglePart;       ///< part of each triangle of geometry.mesh
  std::vector<int> edgePart;           ///< part of each edge polyline
  nlohmann::ordered_json info;         ///< counts, deflection, seconds (for --stats)
  std::string warning;                 ///< faces skipped, or empty
  std::vector<CadFaceSurface> faces;   ///< the exact faces, when asked for (readCad's withSurfaces)
};

/// Reads a CAD file, in a worker process of its own unless options.isolate is off (OpenCASCADE
/// can crash or hang on corrupt files: those become UsageErrors too). Bad input:
/// UsageError("FILE: entity: problem"); CAD support missing from this build: std::runtime_error.
CadGeometry readCad(const std::string& path, const CadOptions& options, bool withSurfaces = false);

/// A scene around one CAD file in one of the contract's styles: "wire" (the edges as shaded
/// wire), "wire-over-surface" (shaded wire over the shaded parts, in the file's colours: the
/// paper's image 11 from a real file), "burnished" (brushed steel, grain along each face's u),
/// "fur" (curved hairs grown on the exact faces, area-correct, only where each face is).
SceneFile sceneForCadFile(const std::string& path, const std::string& style, const CadOptions& options);

/// `wirefur cad-worker FILE OUT ...`: the worker process of readCad (internal, not in the contract).
int runCadWorker(const std::vector<std::string>& args);

}  // namespace wfapp
