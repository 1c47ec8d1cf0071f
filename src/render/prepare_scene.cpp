// Stage "primitives" (render/pipeline.h): camera, lights and shading tables, then every triangle
// and wire segment set up in parallel chunks, joined in a fixed order (the same primitives in the
// same order for any thread count).
#include "render/pipeline.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace wf {

ScreenPolygon screenPolygonOf(const PreparedScene& ps, const Primitive& prim) {
  ScreenPolygon poly;
  poly.count = prim.vertexCount;
  for (int i = 0; i < prim.vertexCount; ++i) {
    poly.x[i] = ps.vertices[prim.firstVertex + i].x;
    poly.y[i] = ps.vertices[prim.firstVertex + i].y;
  }
  return poly;
}

size_t PreparedScene::bytes() const {
  size_t b = primitives.capacity() * sizeof(Primitive) + vertices.capacity() * sizeof(glm::dvec2) +
             triangles.capacity() * sizeof(TriangleAttributes) +
             segments.capacity() * sizeof(SegmentAttributes);
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
  ps.filterTextures = o.filterTextures;
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

  // Work items in a fixed order: chunks of triangles, then chunks of polylines.
  struct Job {
    bool wire;
    std::uint32_t object;
    size_t begin, end;
  };
  std::vector<Job> jobs;
  constexpr size_t kTriChunk = 4096, kLineChunk = 2048;
  for (size_t s = 0; s < scene.surfaces.size(); ++s)
    for (size_t b = 0; b < scene.surfaces[s].mesh.triangles.size(); b += kTriChunk)
      jobs.push_back({false, std::uint32_t(s), b, std::min(b + kTriChunk, scene.surfaces[s].mesh.triangles.size())});
  std::vector<std::uint32_t> tagBase(scene.wires.size());
  std::uint32_t nextTag = std::uint32_t(scene.surfaces.size()) + 1;
  for (size_t w = 0; w < scene.wires.size(); ++w) {
    tagBase[w] = nextTag;
    const size_t n = scene.wires[w].lines.polylineCount();
    nextTag += std::uint32_t(n);
    for (size_t b = 0; b < n; b += kLineChunk) jobs.push_back({true, std::uint32_t(w), b, std::min(b + kLineChunk, n)});
  }
  std::vector<ChunkOut> chunks(jobs.size());
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
    const Job& j = jobs[i];
    if (j.wire) {
      setupPolylines(ps, scene.wires[j.object], std::uint16_t(wireShader[j.object]), tagBase[j.object],
                     j.begin, j.end, chunks[i]);
    } else {
      const SceneSurface& s = scene.surfaces[j.object];
      const Material& m = scene.materials[size_t(std::clamp(s.material, 0, int(scene.materials.size()) - 1))];
      setupTriangles(ps, s, j.object, std::uint16_t(surfaceShader[j.object]), j.object + 1,
                     safeOpacity(m.opacity), j.begin, j.end, chunks[i]);
    }
  });
  // Concatenate in job order (deterministic whatever the thread count).
  std::vector<size_t> rejectedPerObject(scene.surfaces.size() + scene.wires.size(), 0);
  size_t np = 0, nv = 0, nt = 0, ns = 0;
  for (const ChunkOut& c : chunks) np += c.prims.size(), nv += c.verts.size(), nt += c.tris.size(), ns += c.segs.size();
  ps.primitives.reserve(np);
  ps.vertices.reserve(nv);
  ps.triangles.reserve(nt);
  ps.segments.reserve(ns);
  for (size_t i = 0; i < chunks.size(); ++i) {
    ChunkOut& c = chunks[i];
    const std::uint32_t v0 = std::uint32_t(ps.vertices.size());
    const std::uint32_t a0 = std::uint32_t(jobs[i].wire ? ps.segments.size() : ps.triangles.size());
    for (Primitive p : c.prims) {
      p.firstVertex += v0;
      p.attribute += a0;
      ps.primitives.push_back(p);
    }
    ps.vertices.insert(ps.vertices.end(), c.verts.begin(), c.verts.end());
    ps.triangles.insert(ps.triangles.end(), c.tris.begin(), c.tris.end());
    ps.segments.insert(ps.segments.end(), c.segs.begin(), c.segs.end());
    st.triangles += c.triangles;
    st.segments += c.segments;
    st.rejectedNonFinite += c.rejected;
    st.droppedZeroLength += c.zeroLength;
    st.clippedAway += c.clipped;
    st.endOnDiscs += c.endOn;
    rejectedPerObject[jobs[i].wire ? scene.surfaces.size() + jobs[i].object : jobs[i].object] += c.rejected;
    c = ChunkOut{};
  }
  for (size_t i = 0; i < rejectedPerObject.size(); ++i) {
    if (!rejectedPerObject[i]) continue;
    const bool wire = i >= scene.surfaces.size();
    const std::string name = wire ? scene.wires[i - scene.surfaces.size()].name : scene.surfaces[i].name;
    st.warnings.push_back((wire ? "wire '" : "surface '") + name + "': " +
                          std::to_string(rejectedPerObject[i]) +
                          (wire ? " segments" : " triangles") +
                          " with non-finite (NaN/Inf) or missing vertices skipped");
  }
  st.primitives = ps.primitives.size();
  st.setup = secondsSince(t0) - mapSeconds;
  return ps;
}

}  // namespace wf
