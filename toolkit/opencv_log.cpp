#include "toolkit/opencv_log.hpp"

#include <cstdlib>

#include <opencv2/core/utils/logger.hpp>

namespace mdbrief {

void silenceOpenCvLogUnlessAsked() {
  if (!std::getenv("OPENCV_LOG_LEVEL")) cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
}

}  // namespace mdbrief
