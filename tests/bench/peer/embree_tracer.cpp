#include "embree_tracer.h"

#include "render/pipeline.h"

#include <embree3/rtcore.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace wfbench {

namespace {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

struct MemoryMonitor {
  std::atomic<long long> now{0}, peak{0};
  static bool callback(void* self, ssize_t bytes, bool /*post*/) {
    auto* m = static_cast<MemoryMonitor*>(self);
    const long long v = m->now.fetch_add(bytes) + bytes;
    long long p = m->peak.load();
    while (v > p && !m->peak.compare_exchange_weak(p, v)) {
    }
    return true;
  }
};

struct DeviceHolder {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~DeviceHolder() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

void check(RTCDevice d, const char* what) {
  const RTCError e = rtcGetDeviceError(d);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

struct Seen {
  std::uint32_t prim;
  double sx, sy, sd;
  int n;
  glm::vec3 colour;
  bool perSample;
};

}  // namespace

EmbreeResult renderEmbree(const wf::Scene& scene, const wf::RenderOptions& options, const EmbreeOptions& eo) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  EmbreeResult out;
  const int W = options.width, H = options.height, n = eo.samples, n2 = n * n;
  out.image = wf::ImageRGBA(W, H);
  wf::RenderStats st;
  wf::PreparedScene ps = wf::prepareScene(scene, options, st);
  ps.filterTextures = false;  // point samples, averaged (as the reference renderer)
  out.secondsPrepare = since(t0);

  const auto t1 = clock::now();
  DeviceHolder h;
  const std::string config = options.threads > 0 ? "threads=" + std::to_string(options.threads) : "";
  h.device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!h.device) throw std::runtime_error("Embree: rtcNewDevice failed");
  MemoryMonitor memory;
  rtcSetDeviceMemoryMonitorFunction(h.device, &MemoryMonitor::callback, &memory);
  h.scene = rtcNewScene(h.device);
  rtcSetSceneBuildQuality(h.scene, RTC_BUILD_QUALITY_MEDIUM);

  // Embree primID -> the prepared scene's primitive (triangles first, then segments).
  const std::uint32_t triangleCount = std::uint32_t(ps.triangles.size());
  std::vector<std::uint32_t> triOf, segOf;
  if (!eo.curvesOnly)
    for (std::uint32_t i = 0; i < triangleCount; ++i) triOf.push_back(i);
  for (std::uint32_t i = 0; i < ps.segments.size(); ++i) segOf.push_back(triangleCount + i);
  for (std::uint32_t i = 0; i < ps.primitiveCount(); ++i)
    if (ps.opacityOf(i) < 1.0f) ++out.translucent;

  unsigned triGeom = RTC_INVALID_GEOMETRY_ID, curveGeom = RTC_INVALID_GEOMETRY_ID;
  if (!triOf.empty()) {
    RTCGeometry g = rtcNewGeometry(h.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), 3 * triOf.size()));
    auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), triOf.size()));
    check(h.device, "triangle buffers");
    for (size_t k = 0; k < triOf.size(); ++k) {
      const wf::TriangleAttributes& ta = ps.triangleAttributes[triOf[k]];
      const glm::dvec3 q[3] = {ta.p0, ta.p0 + ta.e1, ta.p0 + ta.e2};
      for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) v[9 * k + 3 * c + a] = float(q[c][a]);
      for (int c = 0; c < 3; ++c) ix[3 * k + c] = unsigned(3 * k + c);
    }
    rtcCommitGeometry(g);
    triGeom = rtcAttachGeometry(h.scene, g);
    rtcReleaseGeometry(g);
  }
  if (!segOf.empty()) {
    RTCGeometry g = rtcNewGeometry(h.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), 2 * segOf.size()));
    auto* ix = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), segOf.size()));
    check(h.device, "curve buffers");
    for (size_t k = 0; k < segOf.size(); ++k) {
      // The cylinder the segment's polygon stands for: its axis in eye space, its radius.
      const wf::SegmentPrim& sp = ps.segmentOf(segOf[k]);
      // SegmentPrim holds depth radii (segment_setup.cpp): the world radius comes from the
      // outline's half width instead (w = r f / d times wireWidthFactor; the peer scenes'
      // wires all have a world thickness).
      const glm::dvec3 q[2] = {ps.view.eyePoint(sp.p0.x, sp.p0.y, sp.d0), ps.view.eyePoint(sp.p1.x, sp.p1.y, sp.d1)};
      const double widen = wf::wireWidthFactor(ps.view, q[0], q[1]);
      const float r[2] = {float(sp.w0 / (ps.view.pixelsPerWorld(sp.d0) * widen)),
                          float(sp.w1 / (ps.view.pixelsPerWorld(sp.d1) * widen))};
      for (int c = 0; c < 2; ++c) {
        for (int a = 0; a < 3; ++a) v[8 * k + 4 * c + a] = float(q[c][a]);
        v[8 * k + 4 * c + 3] = r[c];
      }
      ix[k] = unsigned(2 * k);
    }
    rtcCommitGeometry(g);
    curveGeom = rtcAttachGeometry(h.scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(h.scene);
  check(h.device, "building the scene");
  out.triangles = triOf.size();
  out.curves = segOf.size();
  out.secondsBuild = since(t1);

  const auto t2 = clock::now();
  const wf::ViewTransform& view = ps.view;
  const glm::vec4 bg = scene.background;
  auto variesInPixel = [&](std::uint32_t p) { return wf::shadingVariesInPixel(ps, p); };
  auto samplePos = [&](int px, int py, int s, double& x, double& y) {
    const glm::dvec2 q = wf::stratifiedSample(eo.seed, px, py, s, n);  // as the reference renderer
    x = q.x;
    y = q.y;
  };
  // Rays go to Embree in streams (rtcIntersect1M, flagged coherent: the samples of neighbouring
  // pixels), up to kStream rays of whole pixels at a time, which Embree packs into SIMD packets.
  constexpr int kStream = 1024;
  const int pixelsPerStream = std::max(1, kStream / n2);
  wf::inArena(options.threads, [&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, H, 2), [&](const tbb::blocked_range<int>& rows) {
      RTCIntersectContext ctx;
      std::vector<RTCRayHit> stream(size_t(pixelsPerStream) * n2);
      std::vector<Seen> seen;
      for (int py = rows.begin(); py < rows.end(); ++py)
        for (int px0 = 0; px0 < W; px0 += pixelsPerStream) {
          const int px1 = std::min(W, px0 + pixelsPerStream);
          size_t m = 0;
          for (int px = px0; px < px1; ++px)
            for (int s = 0; s < n2; ++s, ++m) {
              double x, y;
              samplePos(px, py, s, x, y);
              RTCRayHit& rh = stream[m];
              glm::dvec3 org(0.0), dir;
              if (view.perspective) {
                dir = view.eyePoint(x, y, 1.0);  // z = -1: the ray's t is the view depth
              } else {
                org = view.eyePoint(x, y, 0.0);
                dir = glm::dvec3(0.0, 0.0, -1.0);
              }
              rh.ray.org_x = float(org.x), rh.ray.org_y = float(org.y), rh.ray.org_z = float(org.z);
              rh.ray.dir_x = float(dir.x), rh.ray.dir_y = float(dir.y), rh.ray.dir_z = float(dir.z);
              rh.ray.tnear = float(view.nearPlane);
              rh.ray.tfar = float(view.farPlane);
              rh.ray.time = 0.0f;
              rh.ray.mask = 0xFFFFFFFFu;
              rh.ray.id = unsigned(m);
              rh.ray.flags = 0;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            }
          rtcInitIntersectContext(&ctx);
          ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
          rtcIntersect1M(h.scene, &ctx, stream.data(), unsigned(m), sizeof(RTCRayHit));
          for (int px = px0; px < px1; ++px) {
            const RTCRayHit* hits = stream.data() + size_t(px - px0) * n2;
            auto primOf = [&](const RTCRayHit& rh) -> std::int32_t {
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
              if (rh.hit.geomID == triGeom) return std::int32_t(triOf[rh.hit.primID]);
              if (rh.hit.geomID == curveGeom) return std::int32_t(segOf[rh.hit.primID]);
              return -1;
            };
            // Each primitive seen: shaded once at the mean of its hits (or at every hit).
            seen.clear();
            auto find = [&](std::uint32_t p) -> Seen& {
              for (Seen& v : seen)
                if (v.prim == p) return v;
              seen.push_back({p, 0, 0, 0, 0, glm::vec3(1.0f), !eo.coverageOnly && variesInPixel(p)});
              return seen.back();
            };
            for (int s = 0; s < n2; ++s) {
              const std::int32_t p = primOf(hits[s]);
              if (p < 0) continue;
              double x, y;
              samplePos(px, py, s, x, y);
              Seen& v = find(std::uint32_t(p));
              v.sx += x, v.sy += y, v.sd += hits[s].ray.tfar, ++v.n;
            }
            if (!eo.coverageOnly)
              for (Seen& v : seen)
                if (!v.perSample)
                  v.colour = wf::shadeFragment(ps, v.prim, v.sx / v.n, v.sy / v.n, v.sd / v.n);
            glm::vec3 rgb(0.0f);
            int covered = 0;
            for (int s = 0; s < n2; ++s) {
              const std::int32_t p = primOf(hits[s]);
              if (p < 0) continue;
              ++covered;
              const Seen& v = find(std::uint32_t(p));
              if (v.perSample) {
                double x, y;
                samplePos(px, py, s, x, y);
                rgb += wf::shadeFragment(ps, v.prim, x, y, hits[s].ray.tfar);
              } else {
                rgb += v.colour;
              }
            }
            const float a = float(covered) / float(n2);
            rgb /= float(n2);
            out.image.at(px, py) = glm::vec4(rgb + (1 - a) * glm::vec3(bg) * bg.w, a + (1 - a) * bg.w);
          }
        }
    });
  });
  out.secondsTrace = since(t2);
  out.rays = size_t(W) * H * n2;
  out.embreeBytes = size_t(std::max(0LL, memory.peak.load()));
  out.secondsTotal = since(t0);
  return out;
}

}  // namespace wfbench
