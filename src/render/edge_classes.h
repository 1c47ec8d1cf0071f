// Edge classes of a CAD model's B-rep edges and of a mesh's edges, and which of them a wire-frame
// draws (`--edges all|sharp|boundary`, `--seams`, `--feature-angle`; docs/cad.md "Edge classes").
// Header-only and free of VTK and OpenCASCADE: the CAD reader (vtk_filters/cad), the mesh edge
// classifier (surface/mesh_edges.h), the scene builder and `wirefur export` share these numbers,
// which are also the values of the "EdgeClass" cell arrays they write.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

namespace wf {

/// What lies on either side of an edge.
enum class EdgeClass : std::uint8_t {
  Boundary = 0,     ///< one face: the border of an open shell or sheet
  Sharp = 1,        ///< two faces meeting at more than the feature angle
  Smooth = 2,       ///< two faces meeting within the feature angle (a fillet's tangent edge)
  Seam = 3,         ///< the same face on both sides (a cylinder's or a sphere's seam)
  Free = 4,         ///< no face: a curve of the model on its own
  NonManifold = 5,  ///< three faces or more
  Silhouette = 6,   ///< not an edge: a silhouette traced for a view (export marks its lines so)
  IsoLine = 7,      ///< not an edge: an iso-parameter line drawn with the edges
};
inline constexpr int kEdgeClasses = 8;

inline const char* edgeClassName(EdgeClass c) {
  switch (c) {
    case EdgeClass::Boundary: return "boundary";
    case EdgeClass::Sharp: return "sharp";
    case EdgeClass::Smooth: return "smooth";
    case EdgeClass::Seam: return "seam";
    case EdgeClass::Free: return "free";
    case EdgeClass::NonManifold: return "non-manifold";
    case EdgeClass::Silhouette: return "silhouette";
    case EdgeClass::IsoLine: return "iso line";
  }
  return "?";
}

/// The default feature angle in degrees: two faces whose normals differ by more along their
/// common edge meet at a sharp edge. Exact CAD data meets at 0 along a fillet (G1); exporters'
/// blends are tangent to 0.1-1 degree; designed creases (chamfers, drafts against a face) are
/// tens of degrees. 10 keeps the second smooth and the third sharp.
inline constexpr double kDefaultFeatureAngle = 10.0;

/// Which edges a wire-frame draws.
struct EdgeSelection {
  enum class Mode : std::uint8_t {
    All,       ///< every edge (seams only with `seams`)
    Sharp,     ///< boundary, sharp, free and non-manifold edges: "hard edges only"
    Boundary,  ///< boundary and free edges: the outline of open shells
  };
  Mode mode = Mode::All;
  bool seams = false;                          ///< draw seam edges too (hidden by default)
  double featureAngle = kDefaultFeatureAngle;  ///< degrees, in [0, 180]

  /// The class of an edge between two faces whose normals differ by at most `angle` degrees
  /// along it (the CAD reader's "EdgeAngle"); NaN (unknown) is sharp, so it is drawn.
  static EdgeClass byAngle(double angle, double featureAngle) {
    return !(angle <= featureAngle) ? EdgeClass::Sharp : EdgeClass::Smooth;
  }

  /// True when an edge of class `c` is drawn. `angle` reclassifies sharp and smooth edges by
  /// this selection's feature angle (the class a reader gave was for its own).
  bool keeps(EdgeClass c, double angle) const {
    if (c == EdgeClass::Sharp || c == EdgeClass::Smooth) c = byAngle(angle, featureAngle);
    if (c == EdgeClass::Seam) return seams;
    if (c == EdgeClass::Silhouette || c == EdgeClass::IsoLine) return true;
    switch (mode) {
      case Mode::All: return true;
      case Mode::Sharp: return c != EdgeClass::Smooth;
      case Mode::Boundary: return c == EdgeClass::Boundary || c == EdgeClass::Free;
    }
    return true;
  }

  bool keepsEverything() const { return mode == Mode::All && seams; }
};

inline bool parseEdgeMode(const std::string& s, EdgeSelection::Mode& mode) {
  if (s == "all") mode = EdgeSelection::Mode::All;
  else if (s == "sharp") mode = EdgeSelection::Mode::Sharp;
  else if (s == "boundary") mode = EdgeSelection::Mode::Boundary;
  else return false;
  return true;
}

inline const char* edgeModeName(EdgeSelection::Mode m) {
  return m == EdgeSelection::Mode::All ? "all" : m == EdgeSelection::Mode::Sharp ? "sharp" : "boundary";
}

}  // namespace wf
