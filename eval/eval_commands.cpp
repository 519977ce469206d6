#include "eval_commands.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>

#include "command_helpers.hpp"
#include "eval_datasets.hpp"
#include "held_out.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "pipeline_experiment.hpp"
#include "pr_experiment.hpp"
#include "simulation.hpp"
#include "timing_table.hpp"
#include "toolkit/data_folders.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "toolkit/option_flags.hpp"

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;

// Refuses, before any work, --camera values whose names cannot name sim's outputs: the name is
// part of file names in --out ("sim_<name>_views.png") and a cell of sim_info.csv, so it is
// letters, digits, '_', '-' and '.' (no '/', no comma) and is given once (issue 45: two cameras
// of one name overwrote each other's files; "../../escape" failed after the whole run).
void checkCameraNames(const std::vector<std::string>& specs) {
  std::set<std::string> names;
  for (const auto& s : specs) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw InputError("--camera " + s + ": expected name=path or name=path#camera-id");
    const std::string name = s.substr(0, eq);
    const bool plain = std::all_of(name.begin(), name.end(), [](unsigned char c) {
      return std::isalnum(c) || c == '_' || c == '-' || c == '.';
    });
    if (!plain || name[0] == '.')
      throw InputError("--camera " + s + ": the name '" + name + "' names output files: use letters, digits, '_', "
                       "'-' and '.' (not first)");
    if (!names.insert(name).second)
      throw InputError("--camera " + s + ": the name '" + name + "' is given twice; each camera's outputs need "
                       "their own name");
  }
}

// "name=path" (or "name=path#id", a rig's camera) pairs of the --camera flags (checkCameraNames);
// a name ending in "_rim" takes the camera's own longest path (to the rim) instead of the shared one.
std::vector<SimCamera> parseCameras(const std::vector<std::string>& specs) {
  std::vector<SimCamera> out;
  for (const auto& s : specs) {
    const auto eq = s.find('=');
    const std::string name = s.substr(0, eq);
    const bool rim = name.size() > 4 && name.compare(name.size() - 4, 4, "_rim") == 0;
    out.push_back({name, loadCameraOrThrow(parseCameraReference(s.substr(eq + 1))), rim ? -1.0 : 0.0});
  }
  return out;
}

void reportExported(const std::string& dir, const UserSequenceFiles& files) {
  std::printf("%s: %zu images, camera.yaml, %zu homographies\n", dir.c_str(), files.images.size(),
              files.homographies.size());
}

}  // namespace

void addSimCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("sim", "The paper's simulation: Graffiti plane seen by moving pinhole / radial / "
                                        "fisheye cameras (projected and detected keypoints)");
  auto o = std::make_shared<SimOptions>();
  auto cams = std::make_shared<std::vector<std::string>>(std::vector<std::string>{
      "pinhole=configs/cameras/pinhole_example.yaml", "radial=configs/cameras/radial_example.yaml",
      "fisheye=configs/cameras/lafida_fisheye0.yaml", "fisheye_rim=configs/cameras/lafida_fisheye0.yaml",
      "double_sphere=configs/cameras/double_sphere_example.yaml"});
  auto docDir = std::make_shared<std::string>();
  auto noProjected = std::make_shared<bool>(false), noDetected = std::make_shared<bool>(false);
  addOpencvDocFlag(cmd, *docDir);
  cmd->add_option("--texture", o->texturePath, "Plane texture (default: graf1.png of --opencv-doc-dir)")
      ->check(inputFileCheck());
  cmd->add_option("--camera", *cams, "name=calibration.yaml, or name=calibration.yaml#id for one camera of a "
                                     "rig file; repeatable (default: pinhole, radial, fisheye (lafida_fisheye0), "
                                     "fisheye_rim, double_sphere of configs/cameras in the working directory); "
                                     "all share the pinhole's path, a name ending in _rim runs to the rim of its "
                                     "lens")
      ->check(inputFileCheck([](const std::string& v) { return cameraReferencePath(v.substr(v.find('=') + 1)); }));
  cmd->add_option("--out", o->outDir, "Output folder for the CSVs and view images")->required();
  cmd->add_option("--views", o->views, "Positions of the distance-evolution path")->check(CLI::Range(2, 1000))->capture_default_str();
  cmd->add_option("--recognition-views", o->recognitionViews, "Views of the recognition sequence")->check(CLI::Range(2, 1000))->capture_default_str();
  cmd->add_option("--keypoints", o->keypoints, "ORB keypoints on the texture")->check(CLI::Range(2, 100000))->capture_default_str();
  addFieldFlag(*cmd, descriptorOptionFields(), "bits", o->bits);
  cmd->add_option("--mask-deg", o->maskDeg, "Mask angle of the projected experiment")->check(CLI::Range(0.1, 89.0))->capture_default_str();
  cmd->add_option("--detected-views", o->detectedViews, "Views of the detected experiment")->check(CLI::Range(2, 1000))->capture_default_str();
  cmd->add_option("--detected-keypoints", o->detectedKeypoints, "Detector budget per view")->check(CLI::Range(10, 100000))->capture_default_str();
  cmd->add_option("--mask-angles", o->maskAngles, "Mask angles compared in the detected experiment")->check(CLI::Range(0.1, 89.0));
  cmd->add_flag("--no-projected", *noProjected, "Skip the projected-keypoint experiment");
  cmd->add_flag("--no-detected", *noDetected, "Skip the detected-keypoint experiment");
  cmd->callback([o, cams, docDir, noProjected, noDetected] {
    if (o->texturePath.empty()) o->texturePath = *docDir + "/graf1.png";
    o->runProjected = !*noProjected;
    o->runDetected = !*noDetected;
    checkCameraNames(*cams);
    // Every file sim writes is a "sim_*" in --out: an input of such a name there may be one.
    std::vector<std::string> inputs{o->texturePath}, outputs;
    for (const auto& spec : *cams) inputs.push_back(parseCameraReference(spec.substr(spec.find('=') + 1)).path);
    for (const auto& input : inputs)
      if (fs::path(input).filename().string().rfind("sim_", 0) == 0)
        outputs.push_back((fs::path(o->outDir) / fs::path(input).filename()).string());
    checkOutputsApart(inputs, outputs);
    const auto cameras = parseCameras(*cams);
    loadGreyOrThrow(o->texturePath);
    // The simulation describes the texture with the default test set.
    requireDisjointTraining({briefFamilyMethod("default", DescriptorKind::DBrief, 256, true)}, {o->texturePath});
    asInputErrors([&] { runSimulation(cameras, *o); });
  });
}

namespace {

// The image sequences of `eval` and `pipelines`: Oxford, rendered fisheye, user data.
struct DatasetFlags {
  std::string oxfordDir = sharedData() + "/oxford-affine";
  std::vector<std::string> sequences = kOxfordSequences;
  // The three fisheye models of configs/cameras (OCamCalib, double sphere, Kannala-Brandt).
  std::vector<std::string> fisheyeCameras{"configs/cameras/lafida_fisheye0.yaml",
                                          "configs/cameras/double_sphere_example.yaml",
                                          "configs/cameras/kannala_brandt_example.yaml"};
  std::vector<std::string> textures;
  std::string opencvDocDir;
  int poses = 6;
  std::vector<std::string> userImages, userHomographies;
  std::string userCamera, userCameraId;
  bool noPerspective = false, noFisheye = false;
};

void addDatasetFlags(CLI::App* cmd, DatasetFlags& d) {
  cmd->add_option("--oxford-dir", d.oxfordDir, "Folder of the Oxford affine sequences (default relative to the "
                                                 "working directory, or $MDBRIEF_DATA/oxford-affine)")
      ->capture_default_str();
  cmd->add_option("--sequences", d.sequences, "Oxford sequences to use")->capture_default_str();
  cmd->add_option("--fisheye-camera", d.fisheyeCameras,
                  "Calibrations to render the fisheye sequences with, file or file#id for one camera of "
                  "a rig file (default: three fisheye models of configs/cameras in the working directory)")
      ->check(inputFileCheck(cameraReferencePath))
      ->capture_default_str();
  cmd->add_option("--texture", d.textures, "Photos rendered as planes (default: img1 of every Oxford sequence "
                                           "found and six photos of --opencv-doc-dir)")
      ->check(inputFileCheck());
  addOpencvDocFlag(cmd, d.opencvDocDir);
  cmd->add_option("--poses", d.poses, "Rendered poses per fisheye sequence")->check(CLI::Range(2, 50))->capture_default_str();
  cmd->add_option("--user-images", d.userImages, "User sequence: reference image first")
      ->check(inputFileCheck());
  cmd->add_option("--user-camera", d.userCamera, "User sequence: camera calibration")
      ->check(inputFileCheck());
  addCameraIdFlag(cmd, d.userCameraId, "--user-camera-id", "--user-camera");
  cmd->add_option("--user-homographies", d.userHomographies,
                  "User sequence: 3x3 bearing-space homographies image 1 -> image k (k = 2..)")
      ->check(inputFileCheck());
  cmd->add_flag("--no-perspective", d.noPerspective, "Skip the Oxford sequences");
  cmd->add_flag("--no-fisheye", d.noFisheye, "Skip the rendered fisheye sequences");
}

// Loads the groups the flags select; `imagePaths` receives the file behind every image, for
// the held-out check.
std::vector<EvalGroup> loadGroups(const DatasetFlags& d, std::vector<std::string>& imagePaths) {
  if (!d.userImages.empty() && d.userCamera.empty()) throw InputError("--user-images needs --user-camera");
  if (!d.noFisheye) requireDistinctLabels(d.fisheyeCameras, "--fisheye-camera");
  std::vector<EvalGroup> groups;
  imagePaths = d.userImages;
  if (!d.noPerspective) {
    EvalGroup g{"perspective", {}};
    for (const auto& s : d.sequences) {
      auto seq = loadOxfordSequence(d.oxfordDir + "/" + s, s);
      if (seq) {
        g.sequences.push_back(std::move(*seq));
        for (int k = 1; k <= 6; ++k) imagePaths.push_back(d.oxfordDir + "/" + s + "/img" + std::to_string(k) + ".png");
      } else {
        std::fprintf(stderr, "eval: skipping Oxford sequence %s: %s/%s not found or incomplete\n", s.c_str(),
                     d.oxfordDir.c_str(), s.c_str());
      }
    }
    groups.push_back(std::move(g));
  }
  if (!d.noFisheye) {
    std::vector<std::string> textures = d.textures;
    if (textures.empty()) {
      for (const auto& s : d.sequences) {
        const std::string p = d.oxfordDir + "/" + s + "/img1.png";
        if (fs::exists(p)) textures.push_back(p);
      }
      // Textured photos of opencv-doc (present on every machine the setup script prepared).
      for (const auto& p : kDocFisheyeTextures) textures.push_back(d.opencvDocDir + "/" + p);
    }
    imagePaths.insert(imagePaths.end(), textures.begin(), textures.end());
    EvalGroup g{"fisheye", {}};
    for (const auto& value : d.fisheyeCameras) {
      const CameraReference camera = parseCameraReference(value);
      const CameraPtr cam = loadCameraOrThrow(camera);
      for (const auto& t : textures) {
        const std::string name = camera.label() + ":" + fs::path(t).parent_path().filename().string() +
                                 "/" + fs::path(t).stem().string();
        g.sequences.push_back(renderedFisheyeSequence(name, loadGreyOrThrow(t), cam, d.poses));
      }
    }
    groups.push_back(std::move(g));
  }
  if (!d.userImages.empty())
    groups.push_back({"user", {loadUserSequence("user", d.userImages, d.userCamera, d.userHomographies, d.userCameraId)}});
  // A group without sequences would replace its results with empty tables (issue 29: a mistyped
  // --oxford-dir emptied eval_summary.csv and exited 0).
  groups.erase(std::remove_if(groups.begin(), groups.end(), [](const EvalGroup& g) { return g.sequences.empty(); }),
               groups.end());
  if (groups.empty())
    throw InputError("no sequence to evaluate (see the messages above); the previous results are left as they were");
  return groups;
}

// Every file the groups were read from, for the check that no output is one of them.
std::vector<std::string> datasetInputs(const DatasetFlags& d, const std::vector<std::string>& imagePaths) {
  std::vector<std::string> inputs = imagePaths;
  for (const auto& value : d.fisheyeCameras) inputs.push_back(parseCameraReference(value).path);
  inputs.insert(inputs.end(), d.userHomographies.begin(), d.userHomographies.end());
  inputs.push_back(d.userCamera);
  return inputs;
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Precision-recall (Mikolajczyk protocol) on Oxford sequences, rendered "
                                         "fisheye sequences and user data");
  struct Args {
    DatasetFlags data;
    PrOptions pr;
    bool quick = false;
    std::vector<std::string> testSets;
    std::string keypointsFrom = "modorb";
    std::vector<double> supportScales;
  };
  auto a = std::make_shared<Args>();
  addDatasetFlags(cmd, a->data);
  cmd->add_option("--keypoints", a->pr.keypoints, "Strongest keypoints per image")->check(CLI::Range(10, 100000))->capture_default_str();
  cmd->add_option("--radius", a->pr.radiusPx, "Ground-truth radius in pixels")->check(CLI::Range(0.1, 100.0))->capture_default_str();
  cmd->add_option("--out", a->pr.outDir, "Output folder for the CSVs")->required();
  cmd->add_flag("--quick", a->quick, "Only the paper's main comparison (no length / test-set study)");
  cmd->add_option("--keypoints-from", a->keypointsFrom,
                  "Keypoints every method but AKAZE describes: the library's detector (modorb, hessian) or an "
                  "OpenCV one")
      ->check(CLI::IsMember(namesOf(kKeypointSourceNames)))
      ->capture_default_str();
  cmd->add_option("--support-scales", a->supportScales,
                  "Only the footprint study: dBRIEF-256 and mdBRIEF-256 at these DescriptorOptions::supportScale values")
      ->check(fieldRangeCheck(descriptorOptionFields(), "support_scale"));
  cmd->add_option("--test-set", a->testSets,
                  "Only the test-set study, with these sets (registry names or JSON files; repeatable)");
  cmd->callback([a] {
    asInputErrors([&] {
      std::vector<std::string> imagePaths;
      const auto groups = loadGroups(a->data, imagePaths);
      std::vector<std::string> inputs = datasetInputs(a->data, imagePaths);
      inputs.insert(inputs.end(), a->testSets.begin(), a->testSets.end());
      std::vector<std::string> outputs{(fs::path(a->pr.outDir) / "eval_summary.csv").string()};
      for (const auto& g : groups)
        outputs.push_back((fs::path(a->pr.outDir) / ("eval_" + g.name + "_curves.csv")).string());
      checkOutputsApart(inputs, outputs);
      a->pr.keypointSource = parseKeypointSource(a->keypointsFrom);
      // The footprint study compares sizes on the keypoints the largest footprint keeps.
      a->pr.commonKeypoints = !a->supportScales.empty();
      std::sort(a->supportScales.begin(), a->supportScales.end());
      const auto methods = !a->supportScales.empty() ? supportScaleStudyMethods(a->supportScales)
                           : a->testSets.empty()     ? standardPrMethods(!a->quick)
                                                     : comparisonSetStudyMethods(a->testSets);
      requireDisjointTraining(methods, imagePaths);
      runPrecisionRecall(groups, methods, a->pr);
    });
  });
}

void addPipelinesCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("pipelines", "Whole pipelines (each detector with its descriptor) at equal keypoint "
                                              "budgets: repeatability and precision-recall");
  struct Args {
    DatasetFlags data;
    PipelineOptions options;
    std::vector<std::string> only;
  };
  auto a = std::make_shared<Args>();
  addDatasetFlags(cmd, a->data);
  cmd->add_option("--budgets", a->options.budgets, "Keypoint budgets per image")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_option("--radius", a->options.radiusPx, "Repeatability and ground-truth radius in pixels")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  cmd->add_option("--out", a->options.outDir, "Output folder for pipelines_summary.csv")->required();
  // The library detectors' options, from their tables (toolkit/option_flags.hpp addFieldFlag).
  DetectorOptions& library = a->options.library;
  const std::string detectors = "the library's detectors";
  addFieldFlag(*cmd, detectorOptionFields(), "hessian_sigma", library.hessianSigma, detectors, library);
  addFieldFlag(*cmd, detectorOptionFields(), "hessian_threshold", library.hessianThreshold, detectors, library);
  addFieldFlag(*cmd, pyramidOptionFields(), "levels", library.pyramid.levels, detectors, library.pyramid);
  addFieldFlag(*cmd, pyramidOptionFields(), "scale_factor", library.pyramid.scaleFactor, detectors, library.pyramid);
  addFieldFlag(*cmd, detectorOptionFields(), "spread", library.spread, detectors, library);
  addFieldFlag(*cmd, detectorOptionFields(), "conformal", library.conformal, detectors, library);
  cmd->add_option("--only", a->only, "Only the pipelines whose name starts with one of these");
  cmd->callback([a] {
    asInputErrors([&] {
      std::vector<std::string> imagePaths;
      const auto groups = loadGroups(a->data, imagePaths);
      checkOutputsApart(datasetInputs(a->data, imagePaths),
                        {(fs::path(a->options.outDir) / "pipelines_summary.csv").string()});
      std::vector<PipelineSpec> pipelines;
      for (const auto& p : standardPipelines())
        if (a->only.empty() || std::any_of(a->only.begin(), a->only.end(), [&](const std::string& prefix) {
              return p.name.rfind(prefix, 0) == 0;
            }))
          pipelines.push_back(p);
      if (pipelines.empty()) throw InputError("--only: no pipeline name starts with any of these");
      std::vector<MethodSpec> descriptors;
      for (const auto& p : pipelines) descriptors.push_back(p.descriptor);
      requireDisjointTraining(descriptors, imagePaths);
      runPipelines(groups, pipelines, a->options);
    });
  });
}

void addTimingCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("timing", "The paper's timing table (detection, description, matching)");
  auto o = std::make_shared<TimingOptions>();
  auto camPath = std::make_shared<std::string>("configs/cameras/lafida_fisheye0.yaml");
  auto camId = std::make_shared<std::string>();
  auto texture = std::make_shared<std::string>();
  auto docDir = std::make_shared<std::string>();
  cmd->add_option("--camera", *camPath, "Camera of the timed images (default relative to the working directory)")
      ->check(inputFileCheck())
      ->capture_default_str();
  addCameraIdFlag(cmd, *camId);
  cmd->add_option("--texture", *texture, "Photo rendered through the camera at 4 poses (default: graf1.png of "
                                         "--opencv-doc-dir)")
      ->check(inputFileCheck());
  addOpencvDocFlag(cmd, *docDir);
  cmd->add_option("--repeats", o->repeats, "Repeats (median reported)")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--keypoints", o->keypoints, "Detector budget")->check(CLI::Range(10, 100000))->capture_default_str();
  cmd->add_option("--out", o->outDir, "Output folder")->required();
  cmd->callback([o, camPath, camId, texture, docDir] {
    const std::string texturePath = texture->empty() ? *docDir + "/graf1.png" : *texture;
    checkOutputsApart({*camPath, texturePath}, {(fs::path(o->outDir) / "timing_table.csv").string()});
    const CameraPtr cam = loadCameraOrThrow(*camPath, *camId);
    const cv::Mat tex = loadGreyOrThrow(texturePath);
    asInputErrors([&] {
      const auto seq = renderedFisheyeSequence("timing", tex, cam, 4);
      const auto rows = measureTimingTable(seq.images, cam, *o);
      writeTimingTable(rows, (fs::path(o->outDir) / "timing_table.csv").string());
      for (const auto& r : rows)
        std::printf("%-7s %-13s %6.0f kp  det %7.2f us/kp  desc %7.2f us/kp  match %7.2f ns/pair  total %7.2f us\n",
                    r.detector.c_str(), r.descriptor.c_str(), r.keypoints, r.detectionUs, r.descriptionUs,
                    r.matchingNs, r.totalUs);
    });
  });
}

void addExportUserSampleCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("export-user-sample",
                                 "Write a rendered sequence as user data (images, camera.yaml, bearing homographies "
                                 "H1toK) for `eval --user-images --user-camera --user-homographies`");
  struct Args {
    std::string camera = "configs/cameras/lafida_fisheye0.yaml", cameraId;
    std::string texture, opencvDocDir;
    std::string out;
    int poses = 6;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--camera", a->camera, "Calibration to render with (default relative to the working directory)")
      ->check(inputFileCheck())
      ->capture_default_str();
  addCameraIdFlag(cmd, a->cameraId);
  cmd->add_option("--texture", a->texture, "Photo rendered as the plane (default: graf3.png of --opencv-doc-dir)")
      ->check(inputFileCheck());
  addOpencvDocFlag(cmd, a->opencvDocDir);
  cmd->add_option("--poses", a->poses, "Images (the poses of the fisheye sequences)")->check(CLI::Range(2, 50))->capture_default_str();
  cmd->add_option("--out", a->out, "Output folder")->required();
  cmd->callback([a] {
    const std::string texture = a->texture.empty() ? a->opencvDocDir + "/graf3.png" : a->texture;
    checkOutputsApart({a->camera, texture}, allPaths(userSequenceFiles(a->out, a->poses)));
    const CameraPtr cam = loadCameraOrThrow(a->camera, a->cameraId);
    const cv::Mat tex = loadGreyOrThrow(texture);
    asInputErrors([&] { reportExported(a->out, exportUserSequence(a->out, tex, cam, a->poses)); });
  });
}

void addExportRotatedViewsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("export-rotated-views",
                                 "Write a real photo and the same lens turned (images, camera.yaml, bearing "
                                 "homographies H1toK = the rotations) for `eval --user-images ...`");
  struct Args {
    std::string photo, camera, cameraId, out;
    int views = 6;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--image", a->photo, "Photo taken with the calibrated camera")
      ->check(inputFileCheck())->required();
  cmd->add_option("--camera", a->camera, "Its calibration")
      ->check(inputFileCheck())->required();
  addCameraIdFlag(cmd, a->cameraId);
  cmd->add_option("--views", a->views, "Images, the photo included")->check(CLI::Range(2, 20))->capture_default_str();
  cmd->add_option("--out", a->out, "Output folder")->required();
  cmd->callback([a] {
    checkOutputsApart({a->camera, a->photo}, allPaths(userSequenceFiles(a->out, a->views)));
    const CameraPtr cam = loadCameraOrThrow(a->camera, a->cameraId);
    const cv::Mat photo = loadGreyOrThrow(a->photo);
    asInputErrors([&] { reportExported(a->out, exportRotatedViews(a->out, photo, cam, a->views)); });
  });
}

void addHeldOutImagesCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("held-out-images",
                                 "Write the digests of every image the default evaluations read (the training's "
                                 "held-out list, configs/held-out-images.txt)");
  auto dataDir = std::make_shared<std::string>(sharedData());
  auto docDir = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto only = std::make_shared<std::vector<std::string>>();
  cmd->add_option("--data", *dataDir, "The shared data folder (Oxford sequences, poster-dev frames, fisheye photos; "
                                      "default relative to the working directory, or $MDBRIEF_DATA)")
      ->capture_default_str();
  addOpencvDocFlag(cmd, *docDir);
  cmd->add_option("--only", *only,
                  "List these images instead (e.g. a validation set used for tuning), labelled by their "
                  "folder and file name");
  cmd->add_option("--out", *out, "Output file")->required();
  cmd->callback([dataDir, docDir, out, only] {
    checkOutputsApart(*only, {*out});
    std::vector<EvaluationImage> images;
    for (const auto& p : *only) {
      loadGreyOrThrow(p);
      images.push_back({p, (fs::path(p).parent_path().filename() / fs::path(p).filename()).string()});
    }
    if (only->empty()) images = defaultEvaluationImages(*dataDir, *docDir);
    if (images.empty()) throw InputError("no evaluation image found (opencv-doc and " + *dataDir + " missing)");
    asInputErrors([&] { internal::writeFileAtomically(*out, heldOutListText(images)); });
    std::printf("%s: %zu images\n", out->c_str(), images.size());
  });
}

}  // namespace mdbrief::eval
