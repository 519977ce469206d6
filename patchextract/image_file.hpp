#pragma once
// Checks on image files that OpenCV's decoders do not report: a truncated JPEG or PNG decodes
// "successfully" with its missing part filled in, which would silently corrupt training
// patches, evaluations and extracted features.
#include <filesystem>
#include <string>

namespace mdbrief::train {

// "" when the file looks complete, else why not: a JPEG (FF D8 ...) must end with its EOI marker
// FF D9 (trailing zero padding allowed), a PNG with its IEND chunk. Other formats are not
// checked (""). An unreadable file gives "cannot read the file".
std::string truncationProblem(const std::filesystem::path& path);

}  // namespace mdbrief::train
