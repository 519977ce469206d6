// `mdbrief-eval tracker`: the tracker benchmark (tracker_experiment.hpp) on the real fisheye
// poster frames, the Oxford sequences, the rendered fisheye sequences and the turned-lens photos.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>

#include "benchmark_datasets.hpp"
#include "command_helpers.hpp"
#include "eval_commands.hpp"
#include "held_out.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "poster_dev.hpp"
#include "stereo_benchmark.hpp"
#include "tracker_experiment.hpp"
#include "scenes/photo_camera.hpp"
#include "toolkit/storage_text.hpp"

namespace mdbrief::eval {
namespace {

struct Args {
  BenchmarkDataPaths paths;
  std::vector<std::string> datasets;
  std::vector<std::string> only;
  std::vector<std::string> library;  // name=options.yml
  TrackerExperimentOptions options;
  StereoOptions stereo;
};

// The data sets of `--datasets`: the image-pair sets, and the stereo pairs scored by their pose.
const std::string kStereoDataset = "stereo";
std::vector<std::string> trackerDatasets() {
  std::vector<std::string> names = kBenchmarkDatasets;
  names.push_back(kStereoDataset);
  return names;
}

// Extra library pipelines: name=file, a cv::FileStorage file of MdBrief::write's schema.
std::vector<TrackerPipeline> libraryPipelines(const std::vector<std::string>& specs) {
  std::vector<TrackerPipeline> out;
  for (const auto& s : specs) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) throw InputError("--library " + s + ": expected name=file");
    const std::string path = s.substr(eq + 1);
    // A regular file of a few options: a FIFO or /dev/zero blocked or ran without end (issue 29).
    if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
      throw InputError(path + ": library options file: " + problem);
    // OpenCV's parsers recurse once per level: a file nested 100,000 deep overflowed the stack
    // (issue 45). The whole text is scanned, as OpenCV reads it all.
    const std::string nesting = scanStorageText(path, std::numeric_limits<std::uintmax_t>::max()).nesting;
    if (!nesting.empty()) throw InputError(path + ": library options file: " + nesting);
    cv::FileStorage fs;
    try {
      fs.open(path, cv::FileStorage::READ);
    } catch (const cv::Exception&) {
    }
    if (!fs.isOpened()) throw InputError(path + ": cannot read as an OpenCV FileStorage file");
    // Options only: the placeholder camera is never used for images.
    auto f2d = MdBrief::create(photoCamera({640, 480}));
    try {
      f2d->read(fs.root());
    } catch (const std::invalid_argument& e) {
      throw InputError(path + ": " + e.what());
    }
    TrackerPipeline p;
    p.name = s.substr(0, eq);
    p.options = f2d->options();
    out.push_back(p);
  }
  return out;
}

}  // namespace

void addMapPosterPointsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("map-poster-points",
                                 "Map pixels of one poster-dev frame into another through the ground truth, as the "
                                 "data set's map_points.py does: prints 'u v valid' per point");
  struct MapArgs {
    std::string dir = sharedData() + "/fisheye/poster-dev";
    int from = 0, to = 0;
    std::vector<double> uv;
  };
  auto a = std::make_shared<MapArgs>();
  cmd->add_option("--poster-dir", a->dir, "The poster-dev folder")->capture_default_str();
  cmd->add_option("from", a->from, "Frame number k of m<k>.jpg the points are in")->required();
  cmd->add_option("to", a->to, "Frame number to map them into")->required();
  cmd->add_option("uv", a->uv, "Pixel coordinates u v (column, row), one pair per point")->required();
  cmd->callback([a] {
    if (a->uv.size() % 2) throw InputError("points: expected pairs of u v");
    asInputErrors([&] {
      const PosterDev poster = loadPosterDev(a->dir);
      const auto index = [&](int id) {
        for (size_t i = 0; i < poster.frames.size(); ++i)
          if (poster.frames[i].id == id) return static_cast<int>(i);
        throw InputError("frame " + std::to_string(id) + " is not in " + a->dir + "/ground_truth.json");
      };
      const int from = index(a->from), to = index(a->to);
      for (size_t k = 0; k < a->uv.size(); k += 2) {
        const auto p = poster.map(from, to, {a->uv[k], a->uv[k + 1]});
        if (p)
          std::printf("%.4f %.4f 1\n", p->x, p->y);
        else
          std::printf("nan nan 0\n");
      }
    });
  });
}

void addTrackerCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("tracker", "What a tracker keeps: ratio-test matches, their precision and robust "
                                            "two-view fits, for every pipeline on real and rendered pairs");
  auto a = std::make_shared<Args>();
  addOpencvDocFlag(cmd, a->paths.opencvDocDir);
  cmd->add_option("--data", a->paths.data, "The shared data folder (poster-dev, Oxford, fisheye photos; default relative "
                                     "to the working directory, or $MDBRIEF_DATA)")
      ->capture_default_str();
  cmd->add_option("--datasets", a->datasets,
                  "Only these data sets: poster-dev, oxford, rendered-fisheye, turned-lens, stereo (the real stereo "
                  "pairs, scored by their known pose; default: every one found; one named here that cannot be read "
                  "is an error)")
      ->check(CLI::IsMember(trackerDatasets()));
  cmd->add_option("--only", a->only, "Only the pipelines whose name starts with one of these");
  cmd->add_option("--library", a->library,
                  "Also evaluate the library with these options: name=file (cv::FileStorage, as MdBrief::write "
                  "writes it); repeatable")
      ->check(inputFileCheck([](const std::string& v) { return v.substr(v.find('=') + 1); }));
  cmd->add_option("--budget", a->options.budget, "Keypoints per image")->check(CLI::Range(10, 100000))->capture_default_str();
  cmd->add_option("--ratios", a->options.ratios, "Ratio-test sweep (1 = mutual nearest neighbours only)")
      ->check(CLI::Range(0.05, 1.0))
      ->capture_default_str();
  cmd->add_option("--fisheye-camera", a->paths.fisheyeCameras, "Calibrations the rendered fisheye sequences use, file or file#id for one camera of a rig file")
      ->check(inputFileCheck(cameraReferencePath))
      ->capture_default_str();
  cmd->add_option("--stereo-refine", a->stereo.refined,
                  "Library pipelines (name prefixes) also scored on the stereo pairs with their matches refined "
                  "(mdbrief/match/match_refinement.hpp; failed refinements dropped), in a row 'NAME + refine'; "
                  "--stereo-refine '' for none")
      ->capture_default_str();
  cmd->add_option("--stereo-budget", a->stereo.budget, "Keypoints per image of the stereo pairs")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_flag("--stereo-matches", a->stereo.writeMatches,
                "Also write stereo_matches.csv (every right match at ratio 0.8: bearings, b's pixels per radian, "
                "signed residual) and stereo_poses.csv (each pair's known pose), for scripts/stereo_pose_check.py");
  cmd->add_option("--out", a->options.outDir,
                  "Output folder for tracker_pairs.csv, tracker_summary.csv, stereo_pairs.csv and stereo_summary.csv "
                  "(and stereo_matches.csv, stereo_poses.csv)")
      ->required();
  cmd->callback([a] {
    requireDistinctLabels(a->paths.fisheyeCameras, "--fisheye-camera");
    std::vector<TrackerPipeline> pipelines;
    for (const auto& p : standardTrackerPipelines())
      if (a->only.empty() || std::any_of(a->only.begin(), a->only.end(),
                                         [&](const std::string& prefix) { return p.name.rfind(prefix, 0) == 0; }))
        pipelines.push_back(p);
    for (auto& p : libraryPipelines(a->library)) pipelines.push_back(std::move(p));
    if (pipelines.empty()) throw InputError("no pipeline selected (--only matches none, no --library)");
    const bool named = !a->datasets.empty();
    std::vector<EvalGroup> groups;
    std::vector<StereoSet> stereo;
    std::vector<std::string> images;
    for (const auto& name : named ? a->datasets : trackerDatasets()) {
      if (name == kStereoDataset) {
        // The real pairs, then the rendered rig (the first --fisheye-camera) whose truth is exact.
        try {
          stereo = loadStereoSets(a->paths.data);
          if (stereo.empty()) throw std::runtime_error(a->paths.data + "/stereo: not found");
          for (const auto& set : stereo)
            for (const auto& pair : set.pairs) images.insert(images.end(), {pair.left, pair.right});
          stereo.push_back(renderedStereoRig(a->paths.opencvDocDir,
                                             loadCameraOrThrow(parseCameraReference(a->paths.fisheyeCameras.at(0)))));
        } catch (const std::exception& e) {
          if (named) throw InputError(name + ": " + e.what());
          std::fprintf(stderr, "tracker: skipping %s: %s\n", name.c_str(), e.what());
          stereo.clear();
        }
        continue;
      }
      std::vector<std::string> read;
      try {
        groups.push_back(loadBenchmarkDataset(name, a->paths, read));
      } catch (const std::exception& e) {
        if (named) throw InputError(name + ": " + e.what());
        std::fprintf(stderr, "tracker: skipping %s: %s\n", name.c_str(), e.what());
        continue;
      }
      images.insert(images.end(), read.begin(), read.end());
    }
    if (groups.empty() && stereo.empty()) throw InputError("no data set could be read (see the messages above)");
    std::vector<std::string> inputs = images;
    for (const auto& value : a->paths.fisheyeCameras) inputs.push_back(parseCameraReference(value).path);
    for (const auto& spec : a->library) inputs.push_back(spec.substr(spec.find('=') + 1));
    checkOutputsApart(inputs, {a->options.outDir + "/tracker_pairs.csv", a->options.outDir + "/tracker_summary.csv",
                               a->options.outDir + "/stereo_pairs.csv", a->options.outDir + "/stereo_summary.csv",
                               a->options.outDir + "/stereo_matches.csv", a->options.outDir + "/stereo_poses.csv"});
    std::vector<MethodSpec> methods;
    for (const auto& p : pipelines)
      if (p.kind == TrackerPipeline::Kind::Library) methods.push_back({p.name, MethodFamily::Library, p.options.descriptor});
    requireDisjointTraining(methods, images);
    asInputErrors([&] {
      if (!groups.empty()) runTracker(groups, pipelines, a->options);
      if (!stereo.empty()) runStereo(stereo, pipelines, a->stereo, a->options.outDir);
    });
  });
}

}  // namespace mdbrief::eval
