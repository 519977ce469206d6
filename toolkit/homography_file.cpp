#include "toolkit/homography_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "mdbrief/internal/atomic_file.hpp"

namespace mdbrief {

cv::Matx33d readHomography(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open the homography file");
  cv::Matx33d h;
  for (int i = 0; i < 9; ++i)
    if (!(in >> h.val[i]) || !std::isfinite(h.val[i]))
      throw std::runtime_error(path.string() + ": expected nine numbers (a 3x3 homography)");
  return h;
}

void writeHomography(const std::filesystem::path& path, const cv::Matx33d& h) {
  std::ostringstream out;
  out.precision(17);
  for (int i = 0; i < 9; ++i) out << h.val[i] << (i % 3 == 2 ? "\n" : " ");
  internal::writeFileAtomically(path, out.str());
}

}  // namespace mdbrief
