#include "detect/hessian.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "detect/gaussian_smoothing.hpp"
#include "detect/hessian_kernels.hpp"

namespace mdbrief::detail {

int hessianTaps(double sigma) { return threeSigmaTaps(sigma); }

namespace {

// The response at column x of the smoothed row b, with a and c the rows above and below and l, r
// the columns beside x: the kernels' operations in their order (hessian_kernels.hpp).
float determinantAt(const float* a, const float* b, const float* c, int l, int x, int r, float scale) {
  const float dxx = (b[l] + b[r]) - 2.f * b[x];
  const float dyy = (a[x] + c[x]) - 2.f * b[x];
  const float dxy = ((c[r] - c[l]) - (a[r] - a[l])) * 0.25f;
  return (dxx * dyy - dxy * dxy) * scale;
}

float responseScale(double sigma) { return static_cast<float>(sigma * sigma * sigma * sigma); }

}  // namespace

PointResponse::PointResponse(const cv::Mat& level8u, double sigma)
    : smoother_(level8u, hessianTaps(sigma), sigma), scale_(responseScale(sigma)) {}

bool PointResponse::exceedsNeighbourhood(int cx, int cy, float value, float& largest) const {
  largest = -INFINITY;
  const cv::Size size = smoother_.levelSize();
  if (cx < 1 || cy < 1 || cx >= size.width - 1 || cy >= size.height - 1) return value > largest;
  // The smoothed 5x5 pixels around (cx, cy), reflected beyond the border as hessianLevel's rows.
  float s[25];
  smoother_.block(cx, cy, s);
  for (int v = 1; v <= 3; ++v)
    for (int u = 1; u <= 3; ++u)
      largest = std::max(largest, determinantAt(s + 5 * (v - 1), s + 5 * v, s + 5 * (v + 1), u - 1, u, u + 1, scale_));
  return value > largest;
}

HessianLevel hessianPoints(const cv::Mat& level8u, double sigma) {
  HessianLevel out;
  out.points.emplace(level8u, sigma);
  return out;
}

HessianLevel hessianLevel(const cv::Mat& level8u, double sigma, bool findCandidates, float threshold, int margin) {
  GaussianRowSmoother smoother(level8u, hessianTaps(sigma), sigma);
  const int rows = level8u.rows, cols = level8u.cols;
  const float scale = responseScale(sigma);
  const hessian_kernels::HessianKernels kernels = hessian_kernels::activeHessianKernels();
  HessianLevel out{cv::Mat(rows, cols, CV_8U), cv::Mat(rows, cols, CV_32F), {}, std::nullopt};
  // The smoothed rows y - 1, y and y + 1 in a ring of three.
  std::vector<float> ring(3 * static_cast<size_t>(cols));
  const auto smoothedRow = [&](int y) { return &ring[static_cast<size_t>(y % 3) * cols]; };
  const auto reflect = [](int i, int n) { return n == 1 ? 0 : i < 0 ? -i : i >= n ? 2 * n - 2 - i : i; };
  // Central second differences and det * sigma^4 of row y, from the smoothed rows around it.
  const auto respond = [&](int y) {
    const float* a = smoothedRow(reflect(y - 1, rows));
    const float* b = smoothedRow(y);
    const float* c = smoothedRow(reflect(y + 1, rows));
    float* r = out.response.ptr<float>(y);
    // The two border columns as the kernel does the others, with reflected neighbours.
    const auto at = [&](int x) { return determinantAt(a, b, c, reflect(x - 1, cols), x, reflect(x + 1, cols), scale); };
    r[0] = at(0);
    kernels.responseRow(a, b, c, cols, scale, r);
    if (cols > 1) r[cols - 1] = at(cols - 1);
  };
  const int edge = std::max(margin, 1);
  const bool search = findCandidates && cols > 2 * edge && rows > 2 * edge;
  std::vector<int32_t> xs(search ? cols + 8 : 0);  // the kernel's room (hessian_kernels.hpp)
  // The maxima of three along the response rows y - 1 .. y + 1, in a ring of three.
  std::vector<float> maxRing(search ? 3 * static_cast<size_t>(cols) : 0);
  const auto maxRow = [&](int y) { return &maxRing[static_cast<size_t>(y % 3) * cols]; };
  // Row y of the response is done: its maxima of three, then the candidates of the row above it.
  const auto searchUpTo = [&](int y) {
    if (!search) return;
    kernels.rowMax3(out.response.ptr<float>(y), cols, maxRow(y));
    const int c = y - 1;
    if (c < edge || c >= rows - edge) return;
    const int found = kernels.candidates(out.response.ptr<float>(c), maxRow(c - 1), maxRow(c), maxRow(c + 1), edge,
                                         cols - edge, threshold, xs.data());
    for (int i = 0; i < found; ++i) out.candidates.emplace_back(xs[i], c);
  };
  for (int y = 0; y < rows; ++y) {
    smoother.next(out.bytes.ptr<uint8_t>(y), smoothedRow(y));
    if (y >= 1) {
      respond(y - 1);
      searchUpTo(y - 1);
    }
  }
  respond(rows - 1);
  searchUpTo(rows - 1);
  return out;
}

namespace {

// Whether `value` exceeds every response of `r` in the 3x3 neighbourhood of pixel (cx, cy) (NaN
// responses aside), and their largest in `largest` (-inf when that pixel is outside the level or
// on its border). Without a branch per response: where a candidate fails is unpredictable.
__attribute__((always_inline)) inline bool exceedsNeighbourhood(const cv::Mat& r, int cx, int cy, float value,
                                                                float& largest) {
  largest = -INFINITY;
  if (cx < 1 || cy < 1 || cx >= r.cols - 1 || cy >= r.rows - 1) return value > largest;
  for (int v = -1; v <= 1; ++v) {
    const float* row = r.ptr<float>(cy + v);
    largest = std::max(std::max(std::max(largest, row[cx - 1]), row[cx]), row[cx + 1]);
  }
  return value > largest;
}

// The pixel of level `to` nearest to each column and each row of level `from`, through the
// input image (the axes map independently): computed once per level pair instead of per
// candidate.
struct PixelMap {
  std::vector<int> column, row;
};
// std::lround's value (halves away from zero) for |v| < 2^31, inline: the library call cost as
// much as the rest of the map, which every frame builds for every level twice.
int roundHalfAway(double v) {
  const int whole = static_cast<int>(v);  // towards zero
  const double fraction = v - whole;        // exact
  return whole + (fraction >= 0.5) - (fraction <= -0.5);
}
// The map of one axis: pixel i of a level whose pixels are fromStep input pixels to the nearest
// of one whose pixels are toStep.
struct AxisMap {
  double fromStep, toStep;
  std::vector<int> nearest;
};
const std::vector<int>& axisMap(double fromStep, double toStep, int n) {
  // The last maps made on this thread: a tracker's frames share their levels' sizes, and building
  // the maps, two divisions a pixel, cost a level's whole search a few per cent.
  constexpr size_t kCached = 64;  // four per level of PyramidOptions' most
  thread_local std::vector<AxisMap> maps;
  for (const AxisMap& m : maps)
    if (m.fromStep == fromStep && m.toStep == toStep && static_cast<int>(m.nearest.size()) == n) return m.nearest;
  if (maps.size() == kCached) maps.erase(maps.begin());
  const LevelGrid from{1.0, {fromStep, fromStep}}, to{1.0, {toStep, toStep}};
  AxisMap m{fromStep, toStep, std::vector<int>(n)};
  for (int i = 0; i < n; ++i) m.nearest[i] = roundHalfAway(to.toLevel(from.toInput(cv::Point2d(i, i))).x);
  maps.push_back(std::move(m));
  return maps.back().nearest;
}
PixelMap pixelMap(const LevelGrid& from, const LevelGrid& to, int cols, int rows) {
  return {axisMap(from.step.x, to.step.x, cols), axisMap(from.step.y, to.step.y, rows)};
}

// Vertex of the parabola through (-1, a), (0, b), (1, c), clamped to [-0.5, 0.5].
float parabolaOffset(float a, float b, float c) {
  const float curvature = a - 2.f * b + c;
  if (!(curvature < 0.f)) return 0.f;
  return std::clamp(0.5f * (a - c) / curvature, -0.5f, 0.5f);
}

// The vertex of the quadratic through the 3x3 neighbourhood (its cross term included), when the
// surface is a cap whose vertex lies within half a pixel; otherwise the two parabolas alone.
void subPixelOffset(const float* above, const float* row, const float* below, float& dx, float& dy) {
  const float gx = 0.5f * (row[1] - row[-1]), gy = 0.5f * (below[0] - above[0]);
  const float hxx = row[-1] - 2.f * row[0] + row[1], hyy = above[0] - 2.f * row[0] + below[0];
  const float hxy = 0.25f * ((below[1] - below[-1]) - (above[1] - above[-1]));
  const float det = hxx * hyy - hxy * hxy;
  if (hxx < 0.f && det > 0.f) {
    const float ox = -(hyy * gx - hxy * gy) / det, oy = -(hxx * gy - hxy * gx) / det;
    if (std::abs(ox) <= 0.5f && std::abs(oy) <= 0.5f) {
      dx = ox;
      dy = oy;
      return;
    }
  }
  dx = parabolaOffset(row[-1], row[0], row[1]);
  dy = parabolaOffset(above[0], row[0], below[0]);
}

}  // namespace

namespace {

// The maxima of level k (0 < k < levels - 1), in scan order.
std::vector<Blob> levelMaxima(const std::vector<HessianLevel>& levels, const std::vector<LevelGrid>& grids, int k,
                              const std::function<bool(int, int, int)>& allowed) {
  std::vector<Blob> blobs;
  const cv::Mat& r = levels[k].response;
  const PixelMap finerPixel = pixelMap(grids[k], grids[k - 1], r.cols, r.rows);
  const PixelMap coarserPixel = pixelMap(grids[k], grids[k + 1], r.cols, r.rows);
  const std::vector<cv::Point>& candidates = levels[k].candidates;
  const cv::Mat& finerResponse = levels[k - 1].response;
  const PointResponse* finerPoints = levels[k - 1].points ? &*levels[k - 1].points : nullptr;
  const cv::Mat& coarserResponse = levels[k + 1].response;
  // The neighbourhoods a candidate reads on its own and the neighbouring levels are fetched a few
  // candidates ahead: scattered over images larger than the cache, each read would otherwise
  // wait for memory. Both lambdas are inlined on purpose: GCC finds an out-of-line function that
  // only prefetches free of side effects and drops the calls to it.
  constexpr size_t kAhead = 8;
  const auto prefetchAround = [](const cv::Mat& image, int x, int y) __attribute__((always_inline)) {
    if (x < 1 || y < 1 || x >= image.cols - 1 || y >= image.rows - 1) return;
    for (int v = -1; v <= 1; ++v) __builtin_prefetch(image.ptr<float>(y + v) + x);
  };
  // Two passes. The first keeps, without a branch per candidate (whether one passes is
  // unpredictable, and a mispredicted branch cost more than the checks), those that pass on their
  // own level and on the neighbouring levels whose responses are whole; the second asks the
  // camera's margin and the finer level computed pixel by pixel of those alone.
  const auto prefetch = [&](size_t i) __attribute__((always_inline)) {
    const int x = candidates[i].x, y = candidates[i].y;
    prefetchAround(r, x, y);
    if (!finerPoints) prefetchAround(finerResponse, finerPixel.column[x], finerPixel.row[y]);
    prefetchAround(coarserResponse, coarserPixel.column[x], coarserPixel.row[y]);
  };
  struct Kept {
    uint32_t index;
    float finer, coarser;
  };
  std::vector<Kept> kept(candidates.size());  // each candidate writes slot `count`, then counts if kept
  size_t count = 0;
  for (size_t i = 0; i < std::min(kAhead, candidates.size()); ++i) prefetch(i);
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (i + kAhead < candidates.size()) prefetch(i + kAhead);
    const int x = candidates[i].x, y = candidates[i].y;
    const float* above = r.ptr<float>(y - 1);
    const float* row = r.ptr<float>(y);
    const float value = row[x];
    // Plateaus: keep the first pixel in scan order only.
    const bool plateau = (row[x - 1] == value) | (above[x - 1] == value) | (above[x] == value) | (above[x + 1] == value);
    Kept& slot = kept[count];
    slot.index = static_cast<uint32_t>(i);
    const bool coarserBelow =
        exceedsNeighbourhood(coarserResponse, coarserPixel.column[x], coarserPixel.row[y], value, slot.coarser);
    // With the finer level pixel by pixel, its check and its maximum come in the second pass.
    const bool finerBelow = finerPoints != nullptr ||
                            exceedsNeighbourhood(finerResponse, finerPixel.column[x], finerPixel.row[y], value, slot.finer);
    count += !plateau & coarserBelow & finerBelow;
  }
  const auto prefetchPoints = [&](size_t j) __attribute__((always_inline)) {
    const int x = candidates[kept[j].index].x, y = candidates[kept[j].index].y;
    finerPoints->prefetch(finerPixel.column[x], finerPixel.row[y]);
  };
  if (finerPoints)
    for (size_t j = 0; j < std::min(kAhead, count); ++j) prefetchPoints(j);
  for (size_t j = 0; j < count; ++j) {
    if (finerPoints && j + kAhead < count) prefetchPoints(j + kAhead);
    const int x = candidates[kept[j].index].x, y = candidates[kept[j].index].y;
    const float* above = r.ptr<float>(y - 1);
    const float* row = r.ptr<float>(y);
    const float* below = r.ptr<float>(y + 1);
    const float value = row[x];
    float finer = kept[j].finer;
    if (!allowed(k, x, y)) continue;
    if (finerPoints && !finerPoints->exceedsNeighbourhood(finerPixel.column[x], finerPixel.row[y], value, finer))
      continue;
    Blob b;
    b.level = k;
    b.x = x;
    b.y = y;
    b.response = value;
    subPixelOffset(above + x, row + x, below + x, b.dx, b.dy);
    b.dlevel = parabolaOffset(finer, value, kept[j].coarser);
    blobs.push_back(b);
  }
  return blobs;
}

}  // namespace

std::vector<Blob> hessianMaxima(const std::vector<HessianLevel>& levels, const std::vector<LevelGrid>& grids,
                                const std::function<bool(int, int, int)>& allowed) {
  const int count = static_cast<int>(levels.size());
  // Only the inner levels: a maximum on the first or last level may be one of a finer or
  // coarser structure, whose scale the pyramid cannot tell (measured: docs/RESULTS.md
  // "Whole pipelines"). Levels in parallel, concatenated in level order.
  std::vector<std::vector<Blob>> perLevel(std::max(count, 0));
  if (count >= 3)
    tbb::parallel_for(1, count - 1, [&](int k) { perLevel[k] = levelMaxima(levels, grids, k, allowed); });
  std::vector<Blob> blobs;
  for (const auto& level : perLevel) blobs.insert(blobs.end(), level.begin(), level.end());
  return blobs;
}

}  // namespace mdbrief::detail
