#include "benchmark_datasets.hpp"

#include <filesystem>
#include <stdexcept>

#include "mdbrief/camera/io.hpp"
#include "poster_dev.hpp"

namespace mdbrief::eval {

namespace fs = std::filesystem;

EvalGroup loadBenchmarkDataset(const std::string& name, const BenchmarkDataPaths& paths, std::vector<std::string>& images) {
  EvalGroup g{name, {}};
  if (name == "poster-dev") {
    const PosterDev poster = loadPosterDev(paths.data + "/fisheye/poster-dev");
    for (const auto& f : poster.frames) images.push_back(f.path);
    g.sequences.push_back(posterDevSequence(poster));
  } else if (name == "oxford") {
    for (const auto& s : kOxfordSequences) {
      const std::string dir = paths.data + "/oxford-affine/" + s;
      auto seq = loadOxfordSequence(dir, s);
      if (!seq) throw std::runtime_error(dir + ": not found or incomplete (img1..6, H1to2p..H1to6p)");
      for (int k = 1; k <= 6; ++k) images.push_back(dir + "/img" + std::to_string(k) + ".png");
      g.sequences.push_back(std::move(*seq));
    }
  } else if (name == "rendered-fisheye") {
    // img1 of every Oxford sequence found and the opencv-doc photos, as `eval` renders them.
    std::vector<std::string> textures;
    for (const auto& s : kOxfordSequences)
      if (const std::string t = paths.data + "/oxford-affine/" + s + "/img1.png"; fs::exists(t)) textures.push_back(t);
    for (const auto& p : kDocFisheyeTextures) textures.push_back(paths.opencvDocDir + "/" + p);
    for (const auto& value : paths.fisheyeCameras) {
      const CameraReference reference = parseCameraReference(value);
      const CameraPtr camera = loadCameraOrThrow(reference);
      for (const auto& t : textures) {
        const std::string seqName = reference.label() + ":" + fs::path(t).parent_path().filename().string() +
                                    "/" + fs::path(t).stem().string();
        g.sequences.push_back(renderedFisheyeSequence(seqName, loadEvaluationImage(t), camera, 6));
      }
    }
    images.insert(images.end(), textures.begin(), textures.end());
  } else if (name == "turned-lens") {
    for (const auto& p : kTurnedLensPhotos) {
      const std::string image = paths.data + "/" + p.image;
      g.sequences.push_back(turnedLensSequence(p.name, loadEvaluationImage(image), loadCamera(paths.data + "/" + p.camera), 6));
      images.push_back(image);
    }
  }
  return g;
}

}  // namespace mdbrief::eval
