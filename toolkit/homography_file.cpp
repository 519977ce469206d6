#include "toolkit/homography_file.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"

namespace mdbrief {

cv::Matx33d readHomography(const std::filesystem::path& path) {
  // Nine numbers; 1 MiB leaves room for any spacing, and refuses /dev/zero or a FIFO.
  std::istringstream in(internal::readInputFile(path, std::uintmax_t{1} << 20, "homography file"));
  cv::Matx33d h;
  for (int i = 0; i < 9; ++i)
    if (!(in >> h.val[i]) || !std::isfinite(h.val[i]))
      throw std::runtime_error(path.string() + ": expected nine numbers (a 3x3 homography)");
  // Issue 45: a tenth number, or a matrix that maps every point to none, passed silently.
  std::string rest;
  if (in >> rest)
    throw std::runtime_error(path.string() + ": expected nine numbers (a 3x3 homography), found more: '" + rest + "'");
  // Singular up to rounding, relative to the scale (a homography is defined up to one).
  const double scale = cv::norm(h, cv::NORM_INF);
  if (!(std::abs(cv::determinant(h)) > 1e-12 * scale * scale * scale))
    throw std::runtime_error(path.string() + ": the homography is singular (determinant 0), not a mapping of the plane");
  return h;
}

void writeHomography(const std::filesystem::path& path, const cv::Matx33d& h) {
  std::ostringstream out;
  out.precision(17);
  for (int i = 0; i < 9; ++i) out << h.val[i] << (i % 3 == 2 ? "\n" : " ");
  internal::writeFileAtomically(path, out.str());
}

}  // namespace mdbrief
