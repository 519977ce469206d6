// Digests of every SIMD kernel's output on fixed inputs (smoothing and its 5x5 blocks, Hessian
// response and maxima, descriptor placement, test bits and centroid, matching and the guided
// matcher's distances, mask weights, the pyramid's bilinear reduction), at every level this CPU runs. Each level must give
// the digests recorded below, which came from x86-64: so a run on AArch64 (scripts/test-arm.sh,
// under qemu-user) shows the same bits as on x86. Free of OpenCV and GoogleTest, so that it cross-builds with the compiler alone;
// prints "N passed, N failed".
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "describe/descriptor_kernels.hpp"
#include "detect/hessian_kernels.hpp"
#include "describe/mask_weight_kernels.hpp"
#include "match/matcher_kernels.hpp"
#include "detect/resize_kernels.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "detect/smoothing_kernels.hpp"

namespace {

using namespace mdbrief;

// FNV-1a, 64 bits.
struct Digest {
  uint64_t h = 1469598103934665603ull;
  void add(const void* data, size_t n) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  template <typename T>
  void add(const std::vector<T>& v) { add(v.data(), v.size() * sizeof(T)); }
  void add(int64_t v) { add(&v, sizeof v); }
};

// A fixed sequence, the same on every CPU (no <random> distribution, whose algorithm may vary).
struct Sequence {
  uint64_t s;
  uint32_t next() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(s >> 33);
  }
};

constexpr int kCols = 203, kRows = 157;  // odd: every vector loop has a tail

std::vector<uint8_t> texture() {
  Sequence r{1};
  std::vector<uint8_t> img(kCols * kRows);
  // Smooth blobs plus noise: maxima of every kind, and plateaus.
  for (int y = 0; y < kRows; ++y)
    for (int x = 0; x < kCols; ++x)
      img[y * kCols + x] = static_cast<uint8_t>((((x * 7) ^ (y * 13)) & 0x3f) + (r.next() % 64) + ((x / 9 + y / 11) % 3) * 40);
  return img;
}

constexpr int kRadii[] = {0, 1, 3, 6, 13, 24};

// Row and column weights summing to 256 and 65536 (their shape does not matter to the arithmetic).
std::pair<std::vector<uint32_t>, std::vector<uint32_t>> smoothingWeights(int radius) {
  std::vector<uint32_t> wr(radius + 1), wc(radius + 1);
  uint32_t left8 = 256, left16 = 65536;
  for (int i = radius; i >= 1; --i) {
    wr[i] = left8 / (2 * (radius + 2)), wc[i] = left16 / (2 * (radius + 2));
    left8 -= 2 * wr[i], left16 -= 2 * wc[i];
  }
  wr[0] = left8, wc[0] = left16;
  return {wr, wc};
}

// levels: the float form at each of kRadii.
uint64_t smoothingDigest(const std::vector<uint8_t>& img, std::vector<std::vector<float>>& levels) {
  const auto k = smoothing_kernels::activeSmoothingKernels();
  Digest d;
  levels.clear();
  for (const int radius : kRadii) {
    const auto [wr, wc] = smoothingWeights(radius);
    std::vector<float>& level = levels.emplace_back();
    // Rows two at a time, as the pyramid smooths them; the digest takes each row's values.
    std::vector<std::vector<uint16_t>> pairs((kRows + 1) / 2, std::vector<uint16_t>(2 * kCols));
    std::vector<uint16_t> padded(2 * (kCols + 2 * radius)), row(kCols);
    for (int q = 0; q < (kRows + 1) / 2; ++q) {
      for (int half = 0; half < 2; ++half) {
        const int y = std::min(2 * q + half, kRows - 1);
        for (int x = 0; x < kCols + 2 * radius; ++x) {
          const int s = x - radius < 0 ? radius - x : x - radius >= kCols ? 2 * kCols - 2 - (x - radius) : x - radius;
          padded[half * (kCols + 2 * radius) + x] = img[y * kCols + s];
        }
      }
      k.rowPair(padded.data() + radius, padded.data() + kCols + 3 * radius, kCols, wr.data(), radius, pairs[q].data());
      for (int half = 0; half < 2 && 2 * q + half < kRows; ++half) {
        for (int x = 0; x < kCols; ++x) row[x] = pairs[q][2 * x + half] ^ 0x8000u;
        d.add(row);
      }
    }
    std::vector<uint8_t> bytes(kCols);
    std::vector<float> floats(kCols);
    for (int y = 0; y < kRows; ++y) {
      // Each row's weight, reflections folded, by pair; weights above 32767 split over terms.
      std::vector<uint32_t> lanes(2 * pairs.size(), 0);
      for (int i = -radius; i <= radius; ++i) {
        const int s = y + i < 0 ? -(y + i) : y + i >= kRows ? 2 * kRows - 2 - (y + i) : y + i;
        lanes[s] += wc[std::abs(i)];
      }
      std::vector<const uint16_t*> terms;
      std::vector<uint32_t> weights;
      for (size_t q = 0; q < pairs.size(); ++q)
        for (uint32_t upper = lanes[2 * q], lower = lanes[2 * q + 1]; upper || lower;) {
          const uint32_t u = std::min(upper, 32767u), l = std::min(lower, 32767u);
          terms.push_back(pairs[q].data()), weights.push_back(u | l << 16);
          upper -= u, lower -= l;
        }
      k.columns(terms.data(), weights.data(), static_cast<int>(terms.size()), kCols, bytes.data(), floats.data());
      d.add(bytes);
      d.add(floats);
      level.insert(level.end(), floats.begin(), floats.end());
    }
  }
  return d.h;
}

// Pixels where block5, which smooths 5x5 pixels only, differs from the passes over the whole image
// (`levels`, smoothingDigest's), over every block whose reads stay inside the image.
int64_t blockMismatches(const std::vector<uint8_t>& img, const std::vector<std::vector<float>>& levels) {
  const auto k = smoothing_kernels::activeSmoothingKernels();
  int64_t mismatches = 0;
  for (size_t r = 0; r < levels.size(); ++r) {
    const int radius = kRadii[r];
    const auto [wr, wc] = smoothingWeights(radius);
    std::vector<const uint8_t*> rows(2 * radius + 5);
    uint32_t fixed[25];
    for (int cy = radius + 2; cy + radius + 2 < kRows; cy += 3)
      for (int cx = radius + 2; cx - radius - 2 + 2 * radius + smoothing_kernels::kBlockSlack <= kCols; cx += 2) {
        for (int t = 0; t < 2 * radius + 5; ++t) rows[t] = &img[(cy - radius - 2 + t) * kCols + cx - radius - 2];
        k.block5(rows.data(), radius, wr.data(), wc.data(), fixed);
        for (int i = 0; i < 25; ++i)
          mismatches += static_cast<float>(static_cast<int>(fixed[i])) * smoothing_kernels::kFixedToUnit !=
                        levels[r][(cy - 2 + i / 5) * kCols + cx - 2 + i % 5];
      }
  }
  return mismatches;
}

// gaussianBlock5 at a few taps, on rows of the texture that it reads beyond the block (whose sums
// it drops); with `mismatches`, counted against the scalar sums in the order the kernel states.
std::vector<float> gaussianBlocks(const hessian_kernels::HessianKernels& k, int* mismatches) {
  std::vector<float> weights(hessian_kernels::kMaxBlockTaps), out;
  for (size_t t = 0; t < weights.size(); ++t) weights[t] = 1.f / static_cast<float>(3 + t);
  const std::vector<uint8_t> pixels = texture();
  for (const int taps : {1, 7, 13, 35, hessian_kernels::kMaxBlockTaps}) {
    std::vector<const uint8_t*> rows(taps + 4);
    for (int q = 0; q < taps + 4; ++q) rows[q] = &pixels[(q + 1) * kCols + 5];
    float block[25];
    k.gaussianBlock5(rows.data(), taps, weights.data(), block);
    out.insert(out.end(), block, block + 25);
    if (!mismatches) continue;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) {
        float sum = 0.f;
        for (int t = 0; t < taps; ++t) {
          float vertical = 0.f;
          for (int u = 0; u < taps; ++u) vertical += weights[u] * static_cast<float>(rows[i + u][j + t]);
          sum += weights[t] * vertical;
        }
        *mismatches += sum != block[5 * i + j];
      }
  }
  return out;
}

uint64_t hessianDigest(const std::vector<float>& level) {
  const auto k = hessian_kernels::activeHessianKernels();
  Digest d;
  std::vector<float> response(level.size(), 0.f);
  for (int y = 1; y + 1 < kRows; ++y)
    k.responseRow(&level[(y - 1) * kCols], &level[y * kCols], &level[(y + 1) * kCols], kCols, 16.f, &response[y * kCols]);
  d.add(response);
  std::vector<float> maxima(response.size(), 0.f);
  for (int y = 0; y < kRows; ++y) k.rowMax3(&response[y * kCols], kCols, &maxima[y * kCols]);
  std::vector<int32_t> xs(kCols + 16);
  int64_t total = 0;
  for (const float threshold : {-1.f, 0.f, 1e-7f, 1e-5f}) {
    for (int y = 2; y + 2 < kRows; ++y) {
      const int n = k.candidates(&response[y * kCols], &maxima[(y - 1) * kCols], &maxima[y * kCols],
                                 &maxima[(y + 1) * kCols], 2, kCols - 2, threshold, xs.data());
      d.add(xs.data(), n * sizeof(int32_t));
      total += n;
    }
  }
  d.add(total);
  d.add(gaussianBlocks(k, nullptr));
  return d.h;
}

uint64_t gaussianBlockMismatches() {
  int mismatches = 0;
  gaussianBlocks(hessian_kernels::activeHessianKernels(), &mismatches);
  return static_cast<uint64_t>(mismatches);
}

uint64_t descriptorDigest(const std::vector<uint8_t>& img) {
  const auto k = descriptor_kernels::activeSamplingKernels();
  Digest d;
  Sequence r{7};
  constexpr int nTests = 512;
  std::vector<int32_t> qa(2 * nTests), qb(2 * nTests);
  for (auto& v : qa) v = static_cast<int32_t>(r.next() % 33) - 16;
  for (auto& v : qb) v = static_cast<int32_t>(r.next() % 33) - 16;
  std::vector<int> x(2 * nTests), y(2 * nTests), u(2 * nTests), v(2 * nTests);
  for (int i = 0; i < 2 * nTests; ++i) u[i] = static_cast<int>(r.next() % 31) - 15, v[i] = static_cast<int>(r.next() % 31) - 15;
  // The samplers read the image's row pairs: digests of the plain image's samples check them too.
  const auto pairRows = smoothing_kernels::activeSmoothingKernels().pairRows;
  std::vector<uint8_t> pairs(2 * kCols * kRows);
  for (int row = 0; row < kRows; ++row)
    pairRows(&img[row * kCols], &img[std::min(row + 1, kRows - 1) * kCols], kCols, &pairs[2 * kCols * row]);
  std::vector<uint8_t> bits(nTests / 8);
  for (int place = 0; place < 60; ++place) {
    // A rotation from a rational parameter: no sin or cos, whose last bit libm may round
    // differently on another CPU.
    const double cx = 30 + place * 2.37, cy = 25 + place * 1.71, t = place * 0.05 - 1.5;
    // Every tenth placement too large for the fixed-point form: the double one places it.
    const double scale = place % 10 == 9 ? 90.0 : 1.0 + place * 0.013;
    const double c = scale * (1 - t * t) / (1 + t * t), s = scale * 2 * t / (1 + t * t);
    // Lengths with every tail of 4, 8 and 16 lanes.
    k.affinePoints(cx, cy, c, -s, s, c, qa.data(), qb.data(), 2 * nTests - 1 - place % 15, x.data(), y.data());
    d.add(x);
    d.add(y);
    const int n = 2 * nTests - (place % 7) * 8;
    k.affinePoints(cx, cy, c, -s, s, c, qa.data(), qb.data(), n, x.data(), y.data());
    d.add(x);
    d.add(y);
    const bool inside = k.allInside(x.data(), y.data(), n, kCols, kRows);
    d.add(int64_t{inside});
    d.add(int64_t{k.allInside(x.data(), y.data(), 3 + place % 5, kCols, kRows)});
    if (!inside || n != 2 * nTests) continue;
    for (const int tests : {32, 256, 512}) {
      // The first points of `tests` tests, then their second points.
      std::vector<int> px(x.begin(), x.begin() + tests), py(y.begin(), y.begin() + tests);
      px.insert(px.end(), x.begin() + nTests, x.begin() + nTests + tests);
      py.insert(py.end(), y.begin() + nTests, y.begin() + nTests + tests);
      k.packBitsBilinear(pairs.data(), 2 * kCols, px.data(), py.data(), tests, bits.data());
      d.add(bits.data(), tests / 8);
    }
    long long m10 = 0, m01 = 0;
    k.centroidMoments(pairs.data(), 2 * kCols, x.data(), y.data(), u.data(), v.data(), 2 * nTests - 8 * (place % 5), m10, m01);
    d.add(int64_t{m10});
    d.add(int64_t{m01});
  }
  return d.h;
}

// How many points of the integer offset grid the affine placement rounds otherwise than the
// double expression it stands for (toFixed), over placements of every kind: scales from a
// hundredth to beyond the fixed-point range, any rotation, and centres on the rounding
// boundaries of sample units (where the fixed-point estimate is ambiguous).
uint64_t affineMismatches() {
  const auto k = descriptor_kernels::activeSamplingKernels();
  using descriptor_kernels::kMaxOffset;
  std::vector<int32_t> qa, qb;
  for (int j = -kMaxOffset; j <= kMaxOffset; ++j)
    for (int i = -kMaxOffset; i <= kMaxOffset; ++i) qa.push_back(i), qb.push_back(j);
  const int n = static_cast<int>(qa.size());
  std::vector<int> x(n), y(n);
  Sequence r{5};
  uint64_t mismatches = 0;
  for (int place = 0; place < 3000; ++place) {
    const auto uniform = [&] { return r.next() / 4294967296.0; };
    double m[4];
    for (double& v : m) v = (uniform() - 0.5) * (place % 50 == 0 ? 300.0 : place % 3 == 0 ? 0.02 : 4.0);
    if (place % 4 == 1) m[1] = m[2] = 0.0, m[0] = m[3] = (place % 7 + 1) / 8.0;  // exact ratios: ties
    // Centres anywhere, or on a multiple of 1/64 px: a half sample unit, a rounding boundary.
    double cx = uniform() * 4000 - 100, cy = uniform() * 3000 - 100;
    if (place % 2) cx = std::floor(cx * 64) / 64, cy = std::floor(cy * 64) / 64;
    k.affinePoints(cx, cy, m[0], m[1], m[2], m[3], qa.data(), qb.data(), n - place % 9, x.data(), y.data());
    for (int i = 0; i < n - place % 9; ++i)
      mismatches += (x[i] != descriptor_kernels::toFixed(cx + m[0] * qa[i] + m[1] * qb[i])) +
                    (y[i] != descriptor_kernels::toFixed(cy + m[2] * qa[i] + m[3] * qb[i]));
  }
  return mismatches;
}

uint64_t matcherDigest() {
  const auto k = matcher_kernels::activeMatcherKernels();
  Digest d;
  Sequence r{11};
  for (const int nwords : {1, 3, 8, 9, 16}) {
    const int count = 77;  // not a multiple of any lane count
    std::vector<uint32_t> desc(count * nwords), mask(count * nwords), weight(count);
    for (auto& w : desc) w = (r.next() % 4) * 0x55555555u;  // few values: many ties
    for (auto& w : mask) w = r.next() % 3 ? 0xffffffffu : r.next();
    for (auto& w : weight) w = 1000 + r.next() % 5000;
    // The kernel's layout: blocks of `lanes` descriptors, word-major, zero padding.
    const int lanes = k.lanes, blocks = (count + lanes - 1) / lanes;
    std::vector<uint32_t> pd(blocks * lanes * nwords, 0), pm(pd.size(), 0), pw(blocks * lanes, 0);
    for (int j = 0; j < count; ++j) {
      for (int w = 0; w < nwords; ++w) {
        pd[(j / lanes * nwords + w) * lanes + j % lanes] = desc[j * nwords + w];
        pm[(j / lanes * nwords + w) * lanes + j % lanes] = mask[j * nwords + w];
      }
      pw[j] = weight[j];
    }
    for (int q = 0; q < 40; ++q) {
      matcher_kernels::QueryRow row;
      for (int w = 0; w < nwords; ++w) row.d[w] = (r.next() % 4) * 0x55555555u, row.l[w] = r.next() % 2 ? ~0u : r.next();
      row.w = 2000 + r.next() % 3000;
      for (const bool masked : {false, true}) {
        const matcher_kernels::TrainView blocked{pd.data(), masked ? pm.data() : nullptr, masked ? pw.data() : nullptr,
                                                 count, nwords, lanes};
        const matcher_kernels::TrainView rowMajor{desc.data(), masked ? mask.data() : nullptr,
                                                  masked ? weight.data() : nullptr, count, nwords, 1};
        // Both kernels give the same nearest two; the digest takes them, not the layout.
        for (const auto n : {k.nearestTwo(row, blocked), k.nearestTwoRows(row, rowMajor)}) {
          d.add(int64_t{n.best});
          d.add(int64_t{n.second});
          d.add(int64_t{n.index});
        }
        // The guided matcher's distances to some rows, in a scattered order.
        const int picked[] = {76, 0, 13, 13, 40, 1, 75};
        uint32_t distances[7];
        k.distancesRows(row, rowMajor, picked, 7, distances);
        d.add(distances, sizeof distances);
      }
    }
  }
  return d.h;
}

uint64_t maskWeightDigest() {
  Digest d;
  Sequence r{13};
  for (const int nwords : {1, 8, 9}) {
    std::vector<uint32_t> rows(50 * nwords), weights(50, 0), ofOnes(nwords * 32 + 1);
    for (auto& w : rows) w = r.next() | r.next() << 1;
    for (size_t i = 0; i < ofOnes.size(); ++i) ofOnes[i] = static_cast<uint32_t>(i * i + 7);
    for (int w = 0; w < nwords; ++w) rows[40 * nwords + w] = 0;  // row 40 empty
    d.add(int64_t(mask_weight_kernels::activeMaskWeights().weights(rows.data(), 50, nwords, ofOnes.data(), weights.data())));
    d.add(weights);
  }
  return d.h;
}

uint64_t resizeDigest(const std::vector<uint8_t>& img) {
  Digest d;
  // The pyramid's chain at 1.2 (each level from the one before), then single reductions: nearly
  // and exactly half, the same size, one axis kept, a few pixels; on the texture and on 0 / 255
  // stripes (every sum's extremes).
  std::vector<uint8_t> stripes(img.size());
  for (size_t i = 0; i < stripes.size(); ++i) stripes[i] = (i / 3 + i / kCols) % 2 ? 255 : 0;
  const std::vector<uint8_t>* sources[] = {&img, &stripes};
  for (const std::vector<uint8_t>* source : sources) {
    std::vector<uint8_t> level = *source;
    int cols = kCols, rows = kRows;
    double scale = 1;
    for (int l = 1; l < 8; ++l) {
      scale *= 1.2;  // not std::pow, which libm may round differently on another CPU
      const int c = static_cast<int>(std::lround(kCols / scale)), r = static_cast<int>(std::lround(kRows / scale));
      std::vector<uint8_t> out(c * r);
      resize_kernels::resizeLinear(level.data(), cols, cols, rows, out.data(), c, c, r);
      d.add(out);
      level = out, cols = c, rows = r;
    }
    for (const auto& [c, r] : {std::pair{102, 79}, {101, 78}, {kCols, kRows}, {kCols, 100}, {60, kRows}, {5, 3}}) {
      std::vector<uint8_t> out(c * r);
      resize_kernels::resizeLinear(source->data(), kCols, kCols, kRows, out.data(), c, c, r);
      d.add(out);
    }
  }
  return d.h;
}

uint64_t halveDigest(const std::vector<uint8_t>& img) {
  Digest d;
  // The texture whole (odd sizes: both borders reflect differently) and its even-sized part, then
  // halved again down to one pixel; and a few pixels' strips.
  std::vector<uint8_t> level = img;
  int cols = kCols, rows = kRows;
  while (cols > 1 || rows > 1) {
    const int c = (cols + 1) / 2, r = (rows + 1) / 2;
    std::vector<uint8_t> out(c * r);
    resize_kernels::halveImage(level.data(), cols, cols, rows, out.data(), c);
    d.add(out);
    level = out, cols = c, rows = r;
  }
  for (const auto& [c, r] : {std::pair{kCols - 1, kRows - 1}, {2, kRows}, {kCols, 3}}) {
    std::vector<uint8_t> out(((c + 1) / 2) * ((r + 1) / 2));
    resize_kernels::halveImage(img.data(), kCols, c, r, out.data(), (c + 1) / 2);
    d.add(out);
  }
  return d.h;
}

// Recorded on x86-64 (every level gives them).
constexpr uint64_t kSmoothing = 0x035e1da41e92902cull, kHessian = 0x10772065b791216aull,
                   kDescriptor = 0x8ee3f96fc7f86082ull, kMatcher = 0xff9176c19ebb9f4aull,
                   kMaskWeights = 0x4bc4bc6c1deb2075ull, kResize = 0xd1e90b4367e98a08ull,
                   kHalve = 0x6387cd288cd79549ull;

}  // namespace

int main(int argc, char** argv) {
  const bool print = argc > 1 && std::strcmp(argv[1], "--print") == 0;
  int passed = 0, failed = 0;
  const std::vector<uint8_t> img = texture();
  for (const SimdLevel level : supportedSimdLevels()) {
    limitSimdLevel(level);
    std::vector<std::vector<float>> smoothed;  // at each of kRadii
    const std::pair<const char*, std::pair<uint64_t, uint64_t>> checks[] = {
        {"smoothing", {smoothingDigest(img, smoothed), kSmoothing}},
        {"block exact", {blockMismatches(img, smoothed), 0}},
        {"hessian", {hessianDigest(smoothed[3]), kHessian}},  // radius 6
        {"block5 exact", {gaussianBlockMismatches(), 0}},
        {"descriptor", {descriptorDigest(img), kDescriptor}},
        {"affine exact", {affineMismatches(), 0}},
        {"matcher", {matcherDigest(), kMatcher}},
        {"mask weights", {maskWeightDigest(), kMaskWeights}},
        {"resize", {resizeDigest(img), kResize}},
        {"halve", {halveDigest(img), kHalve}}};
    for (const auto& [name, digests] : checks) {
      const bool ok = digests.first == digests.second;
      ok ? ++passed : ++failed;
      std::printf("%-8s %-12s %016llx %s\n", toString(level).c_str(), name,
                  static_cast<unsigned long long>(digests.first), ok ? "ok" : print ? "" : "FAILED: differs from x86-64");
    }
  }
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
