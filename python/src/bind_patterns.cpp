// Test sets: the compiled-in ones, JSON files, and off-line learning through the trainer's
// typed API (trainer/training.hpp), the one mdbrief-train runs, so Python gets the tool's
// outputs and determinism.
#include <filesystem>
#include <sstream>
#include <thread>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "option_keywords.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "trainer/pattern_writer.hpp"
#include "trainer/training.hpp"

namespace mdbrief::python {
namespace {

namespace fs = std::filesystem;

py::array_t<int8_t> testsArray(const ComparisonSet& set) {
  py::array_t<int8_t> out({static_cast<py::ssize_t>(set.tests.size()), py::ssize_t{4}});
  for (size_t i = 0; i < set.tests.size(); ++i) {
    const ComparisonPair& t = set.tests[i];
    int8_t* row = out.mutable_data(static_cast<py::ssize_t>(i), 0);
    row[0] = t.x1, row[1] = t.y1, row[2] = t.x2, row[3] = t.y2;
  }
  return out;
}

// The JSON form mdbrief-train writes (<name>.json), which load_pattern and MdBrief read back.
void saveComparisonSet(const ComparisonSet& set, const py::handle& pathArgument) {
  const std::string path = pathFrom(pathArgument, "path");
  PatternDocument document;
  document.name = set.name;
  document.description = "saved by mdbrief.TestSet.save";
  document.tests = set.tests;
  document.trainingImages = set.trainingImages;
  try {
    validate(document);
    internal::writeFileAtomically(path, patternJsonText(document));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

py::tuple comparisonSetState(const ComparisonSet& set) {
  py::list tests;
  for (const ComparisonPair& t : set.tests) tests.append(py::make_tuple(t.x1, t.y1, t.x2, t.y2));
  return py::make_tuple(set.name, tests, set.trainingImages);
}

// A set from Python: tests as (N, 4) rows (x1, y1, x2, y2) of offsets in [-16, 15].
ComparisonSet makeComparisonSet(const std::string& name, const py::handle& rows, const std::vector<std::string>& trainingImages) {
  // Refused here, not first at save(): a set that cannot be saved is refused when it is made.
  try {
    requirePatternName(name);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("ComparisonSet: ") + e.what());
  }
  ComparisonSet set;
  set.name = name;
  set.trainingImages = trainingImages;
  if (!py::isinstance<py::iterable>(rows))
    throw py::type_error(std::string("ComparisonSet: tests must be rows of 4 ints (x1, y1, x2, y2), got ") +
                         Py_TYPE(rows.ptr())->tp_name);
  for (const py::handle row : rows) {
    std::vector<int> v;
    try {
      v = row.cast<std::vector<int>>();
    } catch (const py::cast_error&) {
      // A row of 4 integers one of which no C int holds (2**63) is out of range, not of another
      // type; said with the value as given.
      if (py::isinstance<py::sequence>(row) && !py::isinstance<py::str>(row) && py::len(row) == 4)
        for (const py::handle item : row) {
          const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(item.ptr()));
          if (!index) {
            PyErr_Clear();
            break;
          }
          int overflow = 0;
          const long long x = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
          if (overflow != 0 || x < -16 || x > 15)
            throw py::value_error("ComparisonSet: test " + std::to_string(set.tests.size()) + " has offset " +
                                  std::string(py::str(index)) + " outside [-16, 15]");
        }
      throw py::type_error("ComparisonSet: tests must be rows of 4 ints (x1, y1, x2, y2)");
    }
    if (v.size() != 4) throw py::value_error("ComparisonSet: tests must be rows of 4 ints (x1, y1, x2, y2)");
    for (int x : v)
      if (x < -16 || x > 15)
        throw py::value_error("ComparisonSet: test " + std::to_string(set.tests.size()) + " has offset " +
                              std::to_string(x) + " outside [-16, 15]");
    set.tests.push_back({static_cast<int8_t>(v[0]), static_cast<int8_t>(v[1]), static_cast<int8_t>(v[2]),
                         static_cast<int8_t>(v[3])});
  }
  if (set.tests.empty()) throw py::value_error("ComparisonSet: tests is empty");
  return set;
}

ComparisonSet comparisonSetFromState(const py::tuple& state) {
  const auto texts = [](const py::handle& list) {
    if (!py::isinstance<py::list>(list)) return false;
    for (const py::handle item : list)
      if (!py::isinstance<py::str>(item)) return false;
    return true;
  };
  if (state.size() != 3 || !py::isinstance<py::str>(state[0]) || !texts(state[2]))
    throw py::value_error("ComparisonSet: bad pickled state (ComparisonSet.__getstate__ gives (name: str, tests: list, "
                          "training_images: list of str))");
  return makeComparisonSet(state[0].cast<std::string>(), state[1], state[2].cast<std::vector<std::string>>());
}

ComparisonSet loadPattern(const py::handle& argument) {
  if (py::isinstance<ComparisonSet>(argument)) return argument.cast<ComparisonSet>();
  const std::string nameOrPath = pathFrom(argument, "name_or_path");
  const auto names = builtinComparisonSetNames();
  if (std::find(names.begin(), names.end(), nameOrPath) == names.end()) requireFile(nameOrPath);
  try {
    return resolveComparisonSet(nameOrPath);
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

// Progress that runs Python's signal handlers between the training's batches, so that Ctrl-C
// stops a long training at once, not when it ends (a KeyboardInterrupt came 32 s late). Only the
// calling thread can run them; it takes part in TBB's work, so its calls come batch by batch.
train::TrainProgress signalCheckingProgress() {
  return [check = pythonSignalCheck()](const char*, size_t, size_t) { check(); };
}

// mdbrief.train(**options): TrainOptions from the keywords of its field table, plus `verbose`;
// camera may also be an mdbrief.Camera (saved to a temporary calibration file).
ComparisonSet train(const py::kwargs& kwargs) {
  TemporaryFolder temp;
  py::dict options;
  bool verbose = false;
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (name == "verbose") {
      if (!py::isinstance<py::bool_>(value)) throw py::type_error("verbose must be True or False");
      verbose = value.cast<bool>();
    } else if (name == "camera" && py::isinstance<Camera>(value)) {
      const std::string path = (temp.path / "camera.yaml").string();
      saveCamera(value.cast<const Camera&>(), path);
      options[key] = path;
    } else if (!value.is_none()) {  // None: the option's default
      options[key] = value;
    }
  }
  const train::TrainOptions o = optionsFromKeywords(train::trainOptionFields(), py::kwargs(options), "train",
                                                    [](const train::TrainOptions& t) {
                                                      validateFields(train::trainOptionFields(), t, "TrainOptions");
                                                    });
  // Missing inputs are FileNotFoundError, as Python's own file functions raise.
  for (const auto& folder : o.extraction.imageDirs) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) raiseFileNotFound(folder.string(), "No such image folder");
  }
  if (!o.extraction.cameraPath.empty()) requireFile(o.extraction.cameraPath);
  if (!o.patchesFile.empty()) requireFile(o.patchesFile);
  for (const std::string& file : o.heldOutFiles) requireFile(file);

  train::TrainResult result;
  std::ostringstream log;
  try {
    try {
      py::gil_scoped_release release;
      result = train::train(o, signalCheckingProgress());
    } catch (const PythonSignalRaised&) {
      throw py::error_already_set();
    } catch (const OptionError& e) {
      raiseForKeyword(train::trainOptionFields(), e);
    }
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  if (verbose) {
    train::printTrainSummary(o, result, log);
    py::print(log.str(), py::arg("end") = "");
  }
  return ComparisonSet{result.pattern.name, result.pattern.tests, result.pattern.trainingImages};
}

std::string trainDoc() {
  return "train(**options)\n\n"
         "Off-line learning, as mdbrief-train runs it (docs/training.md); the same options and seed give the\n"
         "same test set, byte for byte. Returns the ComparisonSet. With out (a patterns folder), also writes\n"
         "<name>.hpp, <name>.json and registry.hpp there. camera: a calibration path or an mdbrief.Camera.\n"
         "Paths may be str, bytes or os.PathLike (images and held_out: one, or a list).\n"
         "verbose=True prints mdbrief-train's summary. The options and their defaults (None = the default):\n\n" +
         keywordDoc(train::trainOptionFields(), train::TrainOptions{}) +
         "\nRaises FileNotFoundError for a missing folder or file, ValueError naming the keyword, its range\n"
         "and the value for a bad value, and TypeError for an unknown keyword.";
}

}  // namespace

void bindPatterns(py::module_& m) {
  boundClass<ComparisonSet>(m, "ComparisonSet",
                            "A comparison set (the paper's binary test set): (x1, y1, x2, y2) offsets in the 32x32\n"
                            "patch, in [-16, 15]; comparison d is I(x1, y1) < I(x2, y2). mdbrief.TestSet, its name in\n"
                            "0.2, is the same class object (a deprecated alias).")
      .def(py::init(&makeComparisonSet), py::arg("name"), py::arg("tests"),
           py::arg("training_images") = std::vector<std::string>{},
           "ComparisonSet(name, tests, training_images=()): tests as (N, 4) rows (x1, y1, x2, y2), e.g. an\n"
           "int array; offsets in [-16, 15].")
      .def_readonly("name", &ComparisonSet::name)
      .def_property_readonly("tests", &testsArray, "(N, 4) int8 array, the first rows form the shortest descriptor.")
      .def_readonly("training_images", &ComparisonSet::trainingImages,
                    "Digests of the images the set was learned from (empty for a random set).")
      .def("__len__", [](const ComparisonSet& s) { return s.tests.size(); })
      .def("save", &saveComparisonSet, py::arg("path"),
           "Writes the set as mdbrief-train's <name>.json (path: str, bytes or os.PathLike), atomically;\n"
           "load_pattern(path) and MdBrief(camera, pattern=path) read it back.")
      .def(py::pickle(&comparisonSetState, &comparisonSetFromState))
      .def(
          "first",
          [](const ComparisonSet& s, int n) {
            try {
              return s.first(n);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("n"), "The first n tests (a multiple of 32).")
      .def("__repr__", [](const ComparisonSet& s) {
        return "<mdbrief.ComparisonSet " + s.name + ", " + std::to_string(s.tests.size()) + " tests>";
      });
  // The class's name of 0.2, kept as an alias of the same class object (deprecated).
  m.attr("TestSet") = m.attr("ComparisonSet");

  m.def("patterns", &builtinComparisonSetNames, "Names of the compiled-in test sets, sorted.");
  m.def("default_pattern", &defaultComparisonSetName, "The set MdBrief uses when pattern is ''.");
  m.def("load_pattern", &loadPattern, py::arg("name_or_path"),
        "A compiled-in set by name, a JSON test set file (str, bytes or os.PathLike, as\n"
        "mdbrief-train writes it), or a ComparisonSet (returned as is). The same works as\n"
        "MdBrief(camera, pattern=...).");
  m.def("train", &train, trainDoc().c_str());
}

}  // namespace mdbrief::python
