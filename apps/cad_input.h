// CAD input for the wirefur command (.step .stp .iges .igs .brep .FCStd): read by the VTK
// module WireFur::CAD (vtkWireFurCADReader, OpenCASCADE), which this program opens at run time
// only when a CAD file is given, so that nothing else pays for loading OpenCASCADE (docs/design.md:
// "load OpenCASCADE only for CAD input"). See docs/cad.md.
#pragma once

#include "mesh_io.h"
#include "scene_file.h"

#include "wf_cad_plugin.h"  // vtk_filters/cad: the exact faces' type (no OpenCASCADE in it)

#include <nlohmann/json.hpp>

#include <memory>

#include <string>
#include <vector>

namespace wfapp {

/// True for the CAD extensions (any case).
bool isCadFile(const std::string& path);

/// What a CAD file gives: the faces as one mesh with exact (u, v), Su, Sv and normals and the
/// file's colours; the edges (lines) and iso lines as polylines; per-triangle part index.
struct CadGeometry {
  LoadedGeometry geometry;             ///< mesh: all faces; lines: the edges
  wf::PolylineSet isoLines;
  std::vector<wf::EdgeClass> edgeClasses;  ///< per polyline of geometry.lines (render/edge_classes.h)
  std::vector<float> edgeAngles;           ///< per polyline: degrees between the faces, NaN if none
  std::vector<std::string> partNames;
  std::vector<int> trianglePart;       ///< part of each triangle of geometry.mesh
  std::vector<int> triangleFace;       ///< face (FaceId) of each triangle of geometry.mesh
  nlohmann::ordered_json info;         ///< counts, deflection, seconds (for --stats)
  std::string warning;                 ///< faces skipped, or empty
  /// The exact faces with their trimming masks (wf_cad_plugin.h), when asked for (readCad's
  /// withSurfaces).
  std::vector<WireFurCadFace> faces;
};

/// Reads a CAD file, in a worker process of its own unless options.isolate is off (OpenCASCADE
/// can crash or hang on corrupt files: those become UsageErrors too). Bad input:
/// UsageError("FILE: entity: problem"); CAD support missing from this build: std::runtime_error.
CadGeometry readCad(const std::string& path, const CadOptions& options, bool withSurfaces = false);

/// The CAD model as the core's scene geometry (scene/scene_description.h): its tessellation,
/// edges, iso lines, parts and exact faces.
std::shared_ptr<wf::GeometryData> cadGeometryData(CadGeometry&& cad);

/// A scene around one CAD file in one of the contract's styles: "wire" (the edges as shaded
/// wire), "wire-over-surface" (shaded wire over the shaded parts, in the file's colours: the
/// paper's image 11 from a real file), "burnished" (brushed steel, grain along each face's u),
/// "fur" (curved hairs grown on the exact faces, area-correct, only where each face is).
SceneFile sceneForCadFile(const std::string& path, const std::string& style, const SceneOverrides& overrides);

/// `wirefur cad-worker FILE OUT ...`: the worker process of readCad (internal, not in the contract).
int runCadWorker(const std::vector<std::string>& args);

}  // namespace wfapp
