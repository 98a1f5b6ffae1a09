// Native Embree 3 peer for `cargo run --release --example bench` (section
// (f)): the same height field as POV-Ray's triangles, the same primary
// rays, traced with rtcIntersect1 and with rtcIntersect8 on 4x2 pixel
// tiles, one thread. For the bench only, not CI; the bench builds it with
//   g++ -O3 -march=native -std=c++17 peer.cpp -o peer -lembree3
// (Debian: apt-get install -y libembree-dev g++) and skips it when that
// fails.
//
// usage: peer FIELD.bin RAYS.bin PASSES
//   FIELD.bin: u32 width, u32 depth, then width*depth vertices (3 f32,
//     world space), grid row z = 0 first. Cell (x, z) is split along the
//     diagonal from (x+1, z) to (x, z+1), as POV-Ray and hfray split it:
//     triangles {(x,z), (x+1,z), (x,z+1)} and {(x+1,z+1), (x,z+1), (x+1,z)}.
//   RAYS.bin: u32 width, u32 height, then width*height rays (origin, unit
//     direction: 6 f32), image row 0 first.
// Prints one line of key=value: build_seconds, embree_bytes (peak bytes
// Embree's memory monitor reported), rss_growth_bytes (max RSS growth
// over the build), triangles, hits1, seconds1, hits8, seconds8 (seconds
// per pass over all rays: the median over PASSES passes of this thread's
// CPU time, the two kernels alternating).
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <limits>
#include <vector>
#include <sys/resource.h>

static double thread_cpu() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static long max_rss_bytes() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss * 1024L;
}

static std::atomic<long long> current_bytes{0}, peak_bytes{0};

static bool monitor(void*, ssize_t bytes, bool) {
  long long now = current_bytes += bytes;
  long long peak = peak_bytes.load();
  while (now > peak && !peak_bytes.compare_exchange_weak(peak, now)) {
  }
  return true;
}

static std::vector<char> read_file(const char* path) {
  FILE* f = std::fopen(path, "rb");
  if (!f) {
    std::fprintf(stderr, "peer: cannot open %s\n", path);
    std::exit(1);
  }
  std::vector<char> data;
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.insert(data.end(), buf, buf + n);
  std::fclose(f);
  return data;
}

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: peer FIELD.bin RAYS.bin PASSES\n");
    return 1;
  }
  std::vector<char> field = read_file(argv[1]);
  std::vector<char> rays_file = read_file(argv[2]);
  int passes = std::max(1, std::atoi(argv[3]));
  uint32_t w, d, iw, ih;
  std::memcpy(&w, field.data(), 4);
  std::memcpy(&d, field.data() + 4, 4);
  std::memcpy(&iw, rays_file.data(), 4);
  std::memcpy(&ih, rays_file.data() + 4, 4);
  const float* verts = reinterpret_cast<const float*>(field.data() + 8);
  const float* rays = reinterpret_cast<const float*>(rays_file.data() + 8);

  RTCDevice device = rtcNewDevice("threads=1");
  rtcSetDeviceMemoryMonitorFunction(device, monitor, nullptr);
  long rss0 = max_rss_bytes();
  double t0 = thread_cpu();
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), size_t(w) * d));
  std::copy(verts, verts + size_t(w) * d * 3, vb);
  size_t tris = size_t(w - 1) * (d - 1) * 2;
  unsigned* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
  size_t k = 0;
  for (uint32_t z = 0; z + 1 < d; ++z) {
    for (uint32_t x = 0; x + 1 < w; ++x) {
      unsigned v00 = z * w + x, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      unsigned a[6] = {v00, v10, v01, v11, v01, v10};
      std::copy(a, a + 6, ib + k);
      k += 6;
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  double build = thread_cpu() - t0;
  long rss_growth = max_rss_bytes() - rss0;

  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  const float inf = std::numeric_limits<float>::infinity();
  auto pass1 = [&]() {
    uint64_t hits = 0;
    for (size_t i = 0; i < size_t(iw) * ih; ++i) {
      const float* r = rays + 6 * i;
      RTCRayHit rh;
      rh.ray.org_x = r[0];
      rh.ray.org_y = r[1];
      rh.ray.org_z = r[2];
      rh.ray.dir_x = r[3];
      rh.ray.dir_y = r[4];
      rh.ray.dir_z = r[5];
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = inf;
      rh.ray.mask = ~0u;
      rh.ray.flags = 0;
      rh.ray.time = 0.0f;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
  };
  auto pass8 = [&]() {
    uint64_t hits = 0;
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    for (uint32_t ty = 0; ty < ih; ty += 2) {
      for (uint32_t tx = 0; tx < iw; tx += 4) {
        for (int l = 0; l < 8; ++l) {
          uint32_t px = tx + (l & 3), py = ty + (l >> 2);
          valid[l] = (px < iw && py < ih) ? -1 : 0;
          const float* r = rays + 6 * (size_t(std::min(py, ih - 1)) * iw + std::min(px, iw - 1));
          rh.ray.org_x[l] = r[0];
          rh.ray.org_y[l] = r[1];
          rh.ray.org_z[l] = r[2];
          rh.ray.dir_x[l] = r[3];
          rh.ray.dir_y[l] = r[4];
          rh.ray.dir_z[l] = r[5];
          rh.ray.tnear[l] = 0.0f;
          rh.ray.tfar[l] = inf;
          rh.ray.mask[l] = ~0u;
          rh.ray.flags[l] = 0;
          rh.ray.time[l] = 0.0f;
          rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, scene, &ctx, &rh);
        for (int l = 0; l < 8; ++l)
          hits += valid[l] && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
      }
    }
    return hits;
  };
  uint64_t hits1 = pass1(), hits8 = pass8();  // warm-up
  std::vector<double> s1, s8;
  for (int p = 0; p < passes; ++p) {
    double a = thread_cpu();
    hits1 = pass1();
    double b = thread_cpu();
    hits8 = pass8();
    double c = thread_cpu();
    s1.push_back(b - a);
    s8.push_back(c - b);
  }
  std::printf(
      "build_seconds=%.6f embree_bytes=%lld rss_growth_bytes=%ld triangles=%zu hits1=%llu "
      "seconds1=%.6f hits8=%llu seconds8=%.6f\n",
      build, peak_bytes.load(), rss_growth, tris, (unsigned long long)hits1, median(s1),
      (unsigned long long)hits8, median(s8));
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return 0;
}
