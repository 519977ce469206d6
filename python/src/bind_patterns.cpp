// Test sets: the compiled-in ones, JSON files, and off-line learning through mdbrief-train
// itself (trainer/train_cli.hpp), so Python gets the tool's outputs and determinism.
#include <filesystem>
#include <regex>
#include <sstream>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera_io.hpp"
#include "mdbrief/patterns.hpp"
#include "trainer/train_cli.hpp"

namespace mdbrief::python {
namespace {

namespace fs = std::filesystem;

py::array_t<int8_t> testsArray(const TestSet& set) {
  py::array_t<int8_t> out({static_cast<py::ssize_t>(set.tests.size()), py::ssize_t{4}});
  for (size_t i = 0; i < set.tests.size(); ++i) {
    const TestPair& t = set.tests[i];
    int8_t* row = out.mutable_data(static_cast<py::ssize_t>(i), 0);
    row[0] = t.x1, row[1] = t.y1, row[2] = t.x2, row[3] = t.y2;
  }
  return out;
}

TestSet loadPattern(const py::handle& argument) {
  const std::string nameOrPath = pathFrom(argument, "name_or_path");
  const auto names = builtinTestSetNames();
  if (std::find(names.begin(), names.end(), nameOrPath) == names.end()) requireFile(nameOrPath);
  try {
    return resolveTestSet(nameOrPath);
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
}

// A temporary folder removed when the call ends, however it ends.
struct TemporaryFolder {
  fs::path path;
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "mdbrief_train_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder");
    path = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// One path or an iterable of paths (pathFrom), as file system bytes.
std::vector<std::string> pathList(const py::handle& value, const char* argument) {
  if (value.is_none()) return {};
  if (isPath(value)) return {pathFrom(value, argument)};
  std::vector<std::string> out;
  for (const py::handle item : value) out.push_back(pathFrom(item, argument));
  if (out.empty()) throw py::value_error(std::string(argument) + " is empty");
  return out;
}

TestSet train(const py::handle& images, const std::string& detector, const py::handle& camera, int patches, int tests,
              int seed, const std::string& selection, const std::optional<std::string>& name,
              const py::handle& outArgument, const py::handle& patchesFileArgument, int keypointsPerImage,
              bool renderThroughCamera, const py::handle& heldOut, bool makeDefault, bool verbose) {
  const std::optional<std::string> out =
      outArgument.is_none() ? std::nullopt : std::optional<std::string>(pathFrom(outArgument, "out"));
  const std::optional<std::string> patchesFile =
      patchesFileArgument.is_none() ? std::nullopt
                                    : std::optional<std::string>(pathFrom(patchesFileArgument, "patches_file"));
  TemporaryFolder temp;
  std::vector<std::string> args{"--detector", detector, "--patches", std::to_string(patches), "--tests",
                                std::to_string(tests), "--seed", std::to_string(seed), "--selection", selection,
                                "--keypoints-per-image", std::to_string(keypointsPerImage)};
  for (const std::string& folder : pathList(images, "images")) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) raiseFileNotFound(folder, "No such image folder");
    args.insert(args.end(), {"--images", folder});
  }
  if (!camera.is_none()) {
    std::string path;
    if (py::isinstance<Camera>(camera)) {
      path = (temp.path / "camera.yaml").string();
      saveCamera(camera.cast<const Camera&>(), path);
    } else {
      path = pathFrom(camera, "camera");
      requireFile(path);
    }
    args.insert(args.end(), {"--camera", path});
  }
  if (patchesFile) {
    requireFile(*patchesFile);
    args.insert(args.end(), {"--patches-file", *patchesFile});
  }
  for (const std::string& file : pathList(heldOut, "held_out")) {
    requireFile(file);
    args.insert(args.end(), {"--held-out", file});
  }
  if (name) args.insert(args.end(), {"--name", *name});
  if (renderThroughCamera) args.push_back("--render-through-camera");
  if (makeDefault) {
    if (!out) throw py::value_error("make_default needs out (a patterns folder whose registry it changes)");
    args.push_back("--make-default");
  }
  args.insert(args.end(), {"--out", out ? *out : temp.path.string()});

  std::ostringstream log, err;
  int code = 0;
  {
    py::gil_scoped_release release;
    code = train::runTrainCli(args, log, err);
  }
  if (verbose) py::print(log.str(), py::arg("end") = "");
  if (code != 0) {
    std::string message = err.str();
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw py::value_error(message.rfind("error: ", 0) == 0 ? message.substr(7) : message);
  }
  // The tool names its header in the summary: "tests kept: N -> <folder>/<name>.hpp".
  std::smatch found;
  const std::string text = log.str();
  if (!std::regex_search(text, found, std::regex("tests kept: \\d+ -> (.*)\\.hpp\n")))
    throw std::runtime_error("mdbrief-train did not report its output");
  return loadTestSetJson(found[1].str() + ".json");
}

}  // namespace

void bindPatterns(py::module_& m) {
  py::class_<TestSet>(m, "TestSet", "A binary test set: (x1, y1, x2, y2) offsets in the 32x32 patch, in [-16, 15].")
      .def_readonly("name", &TestSet::name)
      .def_property_readonly("tests", &testsArray, "(N, 4) int8 array, the first rows form the shortest descriptor.")
      .def_readonly("training_images", &TestSet::trainingImages,
                    "Digests of the images the set was learned from (empty for a random set).")
      .def("__len__", [](const TestSet& s) { return s.tests.size(); })
      .def(
          "first",
          [](const TestSet& s, int n) {
            try {
              return s.first(n);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("n"), "The first n tests (a multiple of 32).")
      .def("__repr__", [](const TestSet& s) {
        return "<mdbrief.TestSet " + s.name + ", " + std::to_string(s.tests.size()) + " tests>";
      });

  m.def("patterns", &builtinTestSetNames, "Names of the compiled-in test sets, sorted.");
  m.def("default_pattern", &defaultTestSetName, "The set MdBrief uses when pattern is ''.");
  m.def("load_pattern", &loadPattern, py::arg("name_or_path"),
        "A compiled-in set by name, or a JSON test set file (str, bytes or os.PathLike, as\n"
        "mdbrief-train writes it). The same works as MdBrief(camera, pattern=...).");
  m.def("train", &train, py::arg("images") = py::none(), py::arg("detector") = "orb", py::arg("camera") = py::none(),
        py::arg("patches") = 20000, py::arg("tests") = 512, py::arg("seed") = 1, py::arg("selection") = "paper",
        py::arg("name") = py::none(), py::arg("out") = py::none(), py::arg("patches_file") = py::none(),
        py::arg("keypoints_per_image") = 1000, py::arg("render_through_camera") = false,
        py::arg("held_out") = py::none(), py::arg("make_default") = false, py::arg("verbose") = false,
        R"doc(
Off-line learning, as mdbrief-train runs it (docs/training.md); the same arguments and seed give
the same test set, byte for byte. images: folder(s) of photos (default: the tool's); detector:
'orb', 'akaze' or 'surf'; camera: an mdbrief.Camera or a calibration path (patches on the
tangent plane); selection: 'paper', 'stability' or 'separation'. out: a patterns folder to write
<name>.hpp, <name>.json and registry.hpp into (None: only return the set). Paths may be str,
bytes or os.PathLike (images and held_out: one, or a list). Returns the TestSet.
Raises FileNotFoundError for a missing folder or file and ValueError with the tool's message
otherwise.)doc");
}

}  // namespace mdbrief::python
