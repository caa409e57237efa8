// Peer: the CPU ray-casting ceiling on this machine. Embree 3 (Debian's libembree-dev),
// 8-wide ray packets (4x2 pixel tiles), one thread per core, casting the primary rays of a
// WIDTHxHEIGHT image at the peers' UV sphere plus one shadow ray per hit: the rays shadelab's
// ray tracer casts at --depth 0 on ci/peers/sphere_scene.py's scene.
//
//   embree_caster SEG WIDTH HEIGHT RUNS [THREADS]
//
// Two warm-up frames, then RUNS timed ones (BVH build excluded, timed apart). Prints one JSON
// line: {"peer":"embree", ..., "rays", "median_ms", "min_ms", "max_ms", "mrays_per_s"}.
// Build: g++ -O3 -march=native -o embree_caster embree_caster.cpp -lembree3 -lpthread
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

static int arg(int argc, char** argv, int i, int fallback) {
  if (argc <= i) return fallback;
  char* end = nullptr;
  long v = strtol(argv[i], &end, 10);
  if (*end || v < 1 || v > 1 << 16) {
    fprintf(stderr, "embree_caster: bad argument '%s'\n", argv[i]);
    exit(2);
  }
  return (int)v;
}

int main(int argc, char** argv) {
  if (argc < 2 || argc > 6) {
    fprintf(stderr, "usage: embree_caster SEG [WIDTH HEIGHT RUNS THREADS]\n");
    return 2;
  }
  const int seg = arg(argc, argv, 1, 100), W = arg(argc, argv, 2, 1024), H = arg(argc, argv, 3, 1024);
  const int runs = arg(argc, argv, 4, 5);
  const int threads = arg(argc, argv, 5, std::max(1u, std::thread::hardware_concurrency()));
  const int rings = seg, sectors = 2 * seg;
  std::vector<float> v;
  std::vector<unsigned> ix;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= sectors; ++s) {
      double t = M_PI * r / rings, p = 2 * M_PI * s / sectors;
      v.push_back((float)(sin(t) * cos(p)));
      v.push_back((float)cos(t));
      v.push_back((float)(sin(t) * sin(p)));
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      unsigned a = r * (sectors + 1) + s, b = a + sectors + 1;
      unsigned q[6] = {a, b, a + 1, a + 1, b, b + 1};
      ix.insert(ix.end(), q, q + 6);
    }
  RTCDevice dev = rtcNewDevice(nullptr);
  if (!dev) {
    fprintf(stderr, "embree_caster: rtcNewDevice failed (error %d)\n", (int)rtcGetDeviceError(nullptr));
    return 1;
  }
  auto t0 = std::chrono::steady_clock::now();
  RTCScene scene = rtcNewScene(dev);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vb = (float*)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, v.size() / 3);
  std::copy(v.begin(), v.end(), vb);
  unsigned* ib = (unsigned*)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, ix.size() / 3);
  std::copy(ix.begin(), ix.end(), ib);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  // Camera: eye (0, 0.5, 3) looking at the origin, up +y, fov_y 40; square pixels.
  const float eye[3] = {0, 0.5f, 3.0f}, light[3] = {4, 6, 5};
  float f[3] = {-eye[0], -eye[1], -eye[2]};
  float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (float& x : f) x /= fl;
  float s[3] = {-f[2], 0, f[0]};  // f x (0, 1, 0)
  float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  for (float& x : s) x /= sl;
  const float u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
  const float th = tanf(20 * (float)M_PI / 180), aspect = (float)W / H;

  std::vector<double> times;
  long long rays_total = 0, hits_total = 0;
  for (int it = 0; it < runs + 2; ++it) {
    std::atomic<long long> rays{0}, hits{0};
    auto a = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int tid = 0; tid < threads; ++tid)
      pool.emplace_back([&, tid] {
        long long my_rays = 0, my_hits = 0;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int by = tid * 2; by < H; by += 2 * threads)  // 8-ray packets: 4x2 pixel tiles
          for (int bx = 0; bx < W; bx += 4) {
            RTCRayHit8 rh;
            int valid[8];
            for (int k = 0; k < 8; ++k) {
              int x = bx + (k & 3), y = by + (k >> 2);
              valid[k] = (x < W && y < H) ? -1 : 0;
              float px = ((x + 0.5f) / W * 2 - 1) * th * aspect, py = (1 - (y + 0.5f) / H * 2) * th;
              float d[3] = {px * s[0] + py * u[0] + f[0], px * s[1] + py * u[1] + f[1], px * s[2] + py * u[2] + f[2]};
              float dl = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
              rh.ray.org_x[k] = eye[0];
              rh.ray.org_y[k] = eye[1];
              rh.ray.org_z[k] = eye[2];
              rh.ray.dir_x[k] = d[0] / dl;
              rh.ray.dir_y[k] = d[1] / dl;
              rh.ray.dir_z[k] = d[2] / dl;
              rh.ray.tnear[k] = 0;
              rh.ray.tfar[k] = INFINITY;
              rh.ray.mask[k] = -1;
              rh.ray.flags[k] = 0;
              rh.ray.time[k] = 0;
              rh.ray.id[k] = k;
              rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
              if (valid[k]) ++my_rays;
            }
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            rtcIntersect8(valid, scene, &ctx, &rh);
            RTCRay8 sh;
            int sv[8];
            int n = 0;
            for (int k = 0; k < 8; ++k) {
              sv[k] = 0;
              if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
              float t = rh.ray.tfar[k];
              float p[3] = {rh.ray.org_x[k] + t * rh.ray.dir_x[k], rh.ray.org_y[k] + t * rh.ray.dir_y[k],
                            rh.ray.org_z[k] + t * rh.ray.dir_z[k]};
              float l[3] = {light[0] - p[0], light[1] - p[1], light[2] - p[2]};
              float dist = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
              sh.org_x[k] = p[0];
              sh.org_y[k] = p[1];
              sh.org_z[k] = p[2];
              sh.dir_x[k] = l[0] / dist;
              sh.dir_y[k] = l[1] / dist;
              sh.dir_z[k] = l[2] / dist;
              sh.tnear[k] = 1e-3f;
              sh.tfar[k] = dist;
              sh.mask[k] = -1;
              sh.flags[k] = 0;
              sh.time[k] = 0;
              sh.id[k] = k;
              sv[k] = -1;
              ++n;
            }
            if (n) {
              ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
              rtcOccluded8(sv, scene, &ctx, &sh);
              my_rays += n;
              my_hits += n;
            }
          }
        rays += my_rays;
        hits += my_hits;
      });
    for (auto& t : pool) t.join();
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count();
    if (it >= 2) times.push_back(ms);
    rays_total = rays;
    hits_total = hits;
  }
  std::sort(times.begin(), times.end());
  const size_t m = times.size();
  const double med = m % 2 ? times[m / 2] : (times[m / 2 - 1] + times[m / 2]) / 2;
  printf("{\"peer\":\"embree\",\"version\":\"%s\",\"api\":\"rtcIntersect8/rtcOccluded8\",\"threads\":%d,"
         "\"triangles\":%zu,\"width\":%d,\"height\":%d,\"runs\":%d,\"build_ms\":%.3f,\"rays\":%lld,\"hits\":%lld,"
         "\"median_ms\":%.3f,\"min_ms\":%.3f,\"max_ms\":%.3f,\"mrays_per_s\":%.3f}\n",
         RTC_VERSION_STRING, threads, ix.size() / 3, W, H, runs, build_ms, rays_total, hits_total, med, times.front(),
         times.back(), rays_total / med / 1e3);
  rtcReleaseScene(scene);
  rtcReleaseDevice(dev);
  return 0;
}
