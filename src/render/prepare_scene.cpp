// Stage "primitives" (render/pipeline.h): camera, lights and shading tables, then every triangle
// and wire segment set up in parallel chunks, joined in a fixed order (the same primitives in the
// same order for any thread count).
#include "render/pipeline.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wf {

void screenPolygonOf(const PreparedScene& ps, std::uint32_t i, ScreenPolygon& poly) {
  if (ps.isSegment(i)) {
    segmentPolygon(ps.segmentOf(i), poly);
    return;
  }
  const TrianglePrim& t = ps.triangles[i];
  poly.count = t.vertexCount;
  for (int k = 0; k < t.vertexCount; ++k) {
    poly.x[k] = ps.vertices[t.firstVertex + k].x;
    poly.y[k] = ps.vertices[t.firstVertex + k].y;
  }
}

double primitiveDepthAt(const PreparedScene& ps, std::uint32_t i, double x, double y) { return PrimitiveDepth(ps, i)(x, y); }

PrimitiveDepth::PrimitiveDepth(const PreparedScene& ps, std::uint32_t i) : view_(&ps.view), model_(ps.wireDepth) {
  if (ps.isSegment(i)) {
    seg_ = &ps.segmentOf(i);
    const SegmentFrame fr(*seg_);
    wire_.emplace(Wire{fr, SegmentEndKeys(ps.view, *seg_), SegmentTilt(ps.view, *seg_, fr),
                       segmentUsesCapsule(ps, i) ? WireCapsule(ps.view, *seg_, segmentWidthInPixels(ps, i)) : WireCapsule()});
  } else {
    tri_ = &ps.triangles[i];
  }
}

size_t PreparedScene::primitiveBytes() const {
  return triangles.capacity() * sizeof(TrianglePrim) + vertices.capacity() * sizeof(glm::dvec2) +
         triangleAttributes.capacity() * sizeof(TriangleAttributes) + segments.capacity() * sizeof(SegmentPrim) +
         segmentShading.capacity() * sizeof(SegmentShading) + segmentColours.capacity() * sizeof(SegmentColours) +
         dashPattern.capacity() * sizeof(glm::vec2);
}

size_t PreparedScene::bytes() const {
  size_t b = primitiveBytes();
  for (const ShaderSlot& s : shaders) {
    if (s.wireTables) b += s.wireTables->bytes();
    if (s.surfaceTables) b += s.surfaceTables->bytes();
  }
  return b;
}

PreparedScene prepareScene(const Scene& scene, const RenderOptions& o, RenderStats& st) {
  const auto t0 = std::chrono::steady_clock::now();
  PreparedScene ps;
  ps.scene = &scene;
  ps.path = o.shading;
  ps.wireDepth = o.wireDepth;
  ps.filterTextures = o.filterTextures;
  ps.pixelScale = o.pixelScale;
  const Camera camera = chooseCamera(scene, o, st);
  ps.view = ViewTransform::make(camera, o.width, o.height);
  ps.eyeLights = scene.lightsFollowCamera ? scene.lights.canonical()
                                          : scene.lights.transformed(ps.view.eyeFromWorld).canonical();

  std::vector<int> surfaceShader, wireShader;
  const auto tm = std::chrono::steady_clock::now();
  prepareShaders(ps, scene, o, surfaceShader, wireShader, st);
  const double mapSeconds = secondsSince(tm);

  // Depth-cue range: the wires' depths.
  double cn = 1e300, cf = -1e300;
  for (const SceneWire& w : scene.wires)
    if (w.style == WireStyle::DepthCued)
      for (const glm::dvec3& p : w.lines.points) {
        const double d = -ps.view.toEye(p).z;
        if (std::isfinite(d)) cn = std::min(cn, d), cf = std::max(cf, d);
      }
  ps.cueNear = std::max(cn, ps.view.nearPlane);
  ps.cueFar = std::min(cf, ps.view.farPlane);

  // Stochastic simplification of aggregate wires (off by default: every hair drawn as it is).
  const SimplificationPlan simplification = planSimplification(scene, ps.view, o.simplify, o.pixelScale);
  st.simplifiedHairs = simplification.hairs;
  st.simplifiedKept = simplification.kept;
  st.simplifiedLambda = simplification.minLambda;

  // Work items in a fixed order: chunks of triangles, then chunks of polylines. Each writes
  // straight into the final arrays at the offset of its input (room for every input primitive;
  // a triangle clips to at most 5 vertices); the items are then joined by moving each one's
  // output down to where the previous one ended: no copies of chunks, no regrowth.
  struct Job {
    bool wire;
    std::uint32_t object;
    size_t begin, end;
    size_t offset, vertexOffset;  // where its output starts in the (unjoined) arrays
    SetupCounts counts;
    size_t count = 0, vertexCount = 0;
  };
  std::vector<Job> jobs;
  constexpr size_t kTriChunk = 4096, kLineChunk = 2048;
  size_t triangleRoom = 0, segmentRoom = 0;
  for (size_t s = 0; s < scene.surfaces.size(); ++s)
    for (size_t b = 0; b < scene.surfaces[s].mesh.triangles.size(); b += kTriChunk) {
      const size_t e = std::min(b + kTriChunk, scene.surfaces[s].mesh.triangles.size());
      jobs.push_back({false, std::uint32_t(s), b, e, triangleRoom, 5 * triangleRoom, {}});
      triangleRoom += e - b;
    }
  std::vector<std::uint32_t> tagBase(scene.wires.size());
  std::uint32_t nextTag = std::uint32_t(scene.surfaces.size()) + 1;
  for (size_t w = 0; w < scene.wires.size(); ++w) {
    tagBase[w] = nextTag;
    const PolylineSet& lines = scene.wires[w].lines;
    const size_t n = lines.polylineCount();
    nextTag += std::uint32_t(n);
    for (size_t b = 0; b < n; b += kLineChunk) {
      const size_t e = std::min(b + kLineChunk, n);
      jobs.push_back({true, std::uint32_t(w), b, e, segmentRoom, 0, {}});
      // Room for the most segments polylines b ... e-1 can give (setupPolylines reads polyline li
      // as points [starts[li], min(starts[li + 1], points)): empty or reversed ranges give none).
      for (size_t li = b; li < e; ++li) {
        const size_t a = lines.starts[li], z = std::min<size_t>(lines.starts[li + 1], lines.points.size());
        if (z > a + 1) segmentRoom += z - a - 1;
      }
    }
  }
  if (triangleRoom + segmentRoom > std::numeric_limits<std::uint32_t>::max() / 8)
    throw std::length_error("more than 500 million primitives in one render");
  ps.triangles.resize(triangleRoom);
  ps.triangleAttributes.resize(triangleRoom);
  ps.vertices.resize(5 * triangleRoom);
  ps.segments.resize(segmentRoom);
  ps.segmentShading.resize(segmentRoom);
  bool colours = false;  // some wire gives a segment a colour other than 1 (wireKeepsColours)
  for (size_t w = 0; w < scene.wires.size(); ++w)
    colours = colours || wireKeepsColours(ps, scene.wires[w], std::uint32_t(wireShader[w]));
  if (colours) ps.segmentColours.resize(segmentRoom);
  const bool dashed = keepsDashPatterns(scene);
  if (dashed) ps.dashPattern.resize(segmentRoom);
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
    Job& j = jobs[i];
    if (j.wire) {
      SegmentSink sink{ps.segments.data() + j.offset, ps.segmentShading.data() + j.offset};
      if (colours) sink.colours = ps.segmentColours.data() + j.offset;
      if (dashed) sink.dashPattern = ps.dashPattern.data() + j.offset;
      const WireSimplification& simp = simplification.wires[j.object];
      setupPolylines(ps, scene.wires[j.object], std::uint32_t(wireShader[j.object]), tagBase[j.object], j.begin,
                     j.end, sink, j.counts, simp.scale.empty() ? nullptr : &simp);
      j.count = sink.count;
    } else {
      const SceneSurface& s = scene.surfaces[j.object];
      TriangleSink sink{ps.triangles.data() + j.offset, ps.triangleAttributes.data() + j.offset,
                        ps.vertices.data() + j.vertexOffset};
      setupTriangles(ps, s, j.object, std::uint16_t(surfaceShader[j.object]), j.object + 1, j.begin, j.end, sink,
                     j.counts);
      j.count = sink.count;
      j.vertexCount = sink.vertexCount;
    }
  });
  // Join in job order (deterministic whatever the thread count). An item's output only ever
  // moves down, so moving them in order never overwrites one not yet moved.
  std::vector<size_t> rejectedPerObject(scene.surfaces.size() + scene.wires.size(), 0);
  size_t nt = 0, nv = 0, ns = 0;
  for (const Job& j : jobs) {
    if (j.wire) {
      if (ns != j.offset) {
        std::memmove(static_cast<void*>(ps.segments.data() + ns), ps.segments.data() + j.offset, j.count * sizeof(SegmentPrim));
        std::memmove(static_cast<void*>(ps.segmentShading.data() + ns), ps.segmentShading.data() + j.offset,
                     j.count * sizeof(SegmentShading));
        if (colours)
          std::memmove(static_cast<void*>(ps.segmentColours.data() + ns), ps.segmentColours.data() + j.offset,
                       j.count * sizeof(SegmentColours));
        if (dashed)
          std::memmove(static_cast<void*>(ps.dashPattern.data() + ns), ps.dashPattern.data() + j.offset,
                       j.count * sizeof(glm::vec2));
      }
      ns += j.count;
    } else {
      if (nt != j.offset) {
        std::memmove(static_cast<void*>(ps.triangles.data() + nt), ps.triangles.data() + j.offset, j.count * sizeof(TrianglePrim));
        std::memmove(static_cast<void*>(ps.triangleAttributes.data() + nt), ps.triangleAttributes.data() + j.offset,
                     j.count * sizeof(TriangleAttributes));
      }
      if (nv != j.vertexOffset)
        std::memmove(static_cast<void*>(ps.vertices.data() + nv), ps.vertices.data() + j.vertexOffset, j.vertexCount * sizeof(glm::dvec2));
      for (size_t k = nt; k < nt + j.count; ++k) ps.triangles[k].firstVertex += std::uint32_t(nv);
      nt += j.count;
      nv += j.vertexCount;
    }
    const SetupCounts& c = j.counts;
    st.triangles += c.triangles;
    st.segments += c.segments;
    st.rejectedNonFinite += c.rejected;
    st.droppedZeroLength += c.zeroLength;
    st.clippedAway += c.clipped;
    st.endOnDiscs += c.endOn;
    rejectedPerObject[j.wire ? scene.surfaces.size() + j.object : j.object] += c.rejected;
  }
  // Shrink to what was kept (memory no page of which was touched costs nothing, unless it came
  // from the blocks a previous render left, whose pages are resident; the rest is given back
  // only when much is unused, since shrinking copies).
  auto fit = [](auto& v, size_t n) {
    v.resize(n);
    if (v.capacity() > 2 * n + 4096) v.shrink_to_fit();
  };
  fit(ps.triangles, nt);
  fit(ps.triangleAttributes, nt);
  fit(ps.vertices, nv);
  fit(ps.segments, ns);
  fit(ps.segmentShading, ns);
  if (colours) fit(ps.segmentColours, ns);
  if (dashed) fit(ps.dashPattern, ns);
  for (size_t i = 0; i < rejectedPerObject.size(); ++i) {
    if (!rejectedPerObject[i]) continue;
    const bool wire = i >= scene.surfaces.size();
    const std::string name = wire ? scene.wires[i - scene.surfaces.size()].name : scene.surfaces[i].name;
    st.warnings.push_back((wire ? "wire '" : "surface '") + name + "': " +
                          std::to_string(rejectedPerObject[i]) +
                          (wire ? " segments" : " triangles") +
                          " with non-finite (NaN/Inf) or missing vertices skipped");
  }
  // A wire whose thickness is no positive finite number draws nothing (its segments counted as
  // clipped away): said once, by name, rather than left to the count.
  for (const SceneWire& w : scene.wires)
    if (!(w.thickness > 0.0 && std::isfinite(w.thickness)) && w.lines.points.size() > 1) {
      std::ostringstream line;
      line << "wire '" << w.name << "': thickness " << w.thickness << " is not a positive finite number; not drawn";
      st.warnings.push_back(line.str());
    }
  st.primitives = ps.primitiveCount();
  st.setup = secondsSince(t0) - mapSeconds;
  return ps;
}

}  // namespace wf
