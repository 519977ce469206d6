#include "toolkit/homography_file.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"

namespace mdbrief {

cv::Matx33d readHomography(const std::filesystem::path& path) {
  // Nine numbers; 1 MiB leaves room for any spacing and comment, and refuses /dev/zero or a FIFO.
  std::istringstream in(internal::readInputFile(path, std::uintmax_t{1} << 20, "homography file"));
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
