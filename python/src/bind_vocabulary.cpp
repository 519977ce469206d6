// mdbrief.Vocabulary: a vocabulary of binary words (vocabulary.hpp), its files (the library's
// binary file and DBoW2/DBoW3 text) and the transform of descriptors into bags of words.
#include "bindings.hpp"
#include "bow_conversions.hpp"
#include "conversions.hpp"
#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/recognition/vocabulary.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"

namespace mdbrief::python {
namespace {

// Reads a vocabulary file: FileNotFoundError when nothing is there, ValueError naming the file
// and the problem for a file that is not a usable vocabulary (as load_camera).
Vocabulary readVocabulary(const py::handle& pathArgument, Vocabulary (*reader)(const std::string&)) {
  const std::string path = pathFrom(pathArgument, "path");
  requireFile(path);
  try {
    return reader(path);
  } catch (const FileFormatError& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

void bindVocabulary(py::module_& m) {
  boundClass<Vocabulary>(m, "Vocabulary", R"doc(
A vocabulary of binary visual words for place recognition: a tree of k-majority centroids (and,
masked, of the masks of the bits the members agree on), trained by mdbrief-train-vocabulary.
Read one with Vocabulary.load (the library's file) or Vocabulary.import_dbow2_text (DBoW2/DBoW3
text of plain descriptors, e.g. ORB-SLAM's ORBvoc.txt). Immutable; docs/vocabulary.md.)doc")
      .def_static(
          "load", [](const py::handle& path) { return readVocabulary(path, &Vocabulary::load); }, py::arg("path"),
          "Reads the library's binary vocabulary file (str, bytes or os.PathLike), checked. Raises "
          "FileNotFoundError for a missing file and ValueError naming the file and the problem for a bad one.")
      .def_static(
          "import_dbow2_text", [](const py::handle& path) { return readVocabulary(path, &importDbow2Text); },
          py::arg("path"), "Reads a DBoW2/DBoW3 text vocabulary (a plain one); errors as load.")
      .def(
          "save", [](const Vocabulary& v, const py::handle& path) { v.save(pathFrom(path, "path")); }, py::arg("path"),
          "Writes the binary file atomically; the bytes depend only on the content.")
      .def(
          "export_dbow2_text",
          [](const Vocabulary& v, const py::handle& path) { exportDbow2Text(v, pathFrom(path, "path")); },
          py::arg("path"), "Writes the DBoW2 text file atomically; ValueError for a masked vocabulary.")
      .def_property_readonly("bits", &Vocabulary::bits)
      .def_property_readonly("branching", &Vocabulary::branching, "k: children per node at most")
      .def_property_readonly("depth", &Vocabulary::depth, "L: levels at most")
      .def_property_readonly("masked", &Vocabulary::masked, "Nodes carry masks and meet descriptors masked")
      .def_property_readonly("weighting", [](const Vocabulary& v) { return toString(v.weighting()); })
      .def_property_readonly("word_count", &Vocabulary::wordCount)
      .def_property_readonly("node_count", &Vocabulary::nodeCount)
      .def_property_readonly("fingerprint", &Vocabulary::fingerprint,
                             "Checksum of the content: equal for vocabularies with the same content")
      .def(
          "word_weight",
          [](const Vocabulary& v, int64_t word) {
            if (word < 0 || static_cast<uint64_t>(word) >= v.wordCount())
              throw py::index_error("word " + std::to_string(word) + " is not below word_count " +
                                    std::to_string(v.wordCount()));
            return v.wordWeight(static_cast<uint32_t>(word));
          },
          py::arg("word"))
      .def(
          "transform",
          [](const Vocabulary& v, const py::handle& descriptors, const py::handle& masks, int directIndexDepth) {
            py::object keepD, keepM;
            const cv::Mat d = descriptorsFromArray(descriptors, "descriptors", keepD);
            cv::Mat mk;
            if (!masks.is_none()) mk = descriptorsFromArray(masks, "masks", keepM);
            TransformOptions options;
            options.directIndexDepth = directIndexDepth;
            BowTransform t;
            {
              py::gil_scoped_release release;
              t = v.transform(d, mk, options);
            }
            py::dict direct;
            for (const auto& e : t.direct) {
              py::array_t<int32_t> rows(static_cast<py::ssize_t>(e.features.size()));
              std::copy(e.features.begin(), e.features.end(), rows.mutable_data());
              direct[py::int_(e.node)] = rows;
            }
            py::array_t<uint32_t> words(static_cast<py::ssize_t>(t.words.size()));
            std::copy(t.words.begin(), t.words.end(), words.mutable_data());
            return py::make_tuple(bowToPython(t.bow), direct, words);
          },
          py::arg("descriptors"), py::arg("masks") = py::none(), py::kw_only(),
          py::arg("direct_index_depth") = TransformOptions{}.directIndexDepth, R"doc(
Quantises descriptors ((N, bits/8) uint8) with their masks (the same shape, or None: every bit
trusted; a plain vocabulary ignores them). Returns (bow, direct_index, words):
- bow: {word: value}, ascending words, values L1-normalised with the vocabulary's weighting;
- direct_index: {node: int32 array of descriptor rows} for the nodes at direct_index_depth
  (1 = the root's children), for guided matching of features under the same node;
- words: (N,) uint32, the word of every row.
Raises ValueError when the width differs from the vocabulary's or the masks' shape from the
descriptors'.)doc")
      .def(
          "words",
          [](const Vocabulary& v, const py::handle& descriptors, const py::handle& masks) {
            py::object keepD, keepM;
            const cv::Mat d = descriptorsFromArray(descriptors, "descriptors", keepD);
            cv::Mat mk;
            if (!masks.is_none()) mk = descriptorsFromArray(masks, "masks", keepM);
            std::vector<uint32_t> w;
            {
              py::gil_scoped_release release;
              w = v.words(d, mk);
            }
            py::array_t<uint32_t> out(static_cast<py::ssize_t>(w.size()));
            std::copy(w.begin(), w.end(), out.mutable_data());
            return out;
          },
          py::arg("descriptors"), py::arg("masks") = py::none(), "Only the words of transform: (N,) uint32.")
      .def("__repr__", [](const Vocabulary& v) {
        return "<mdbrief.Vocabulary " + std::to_string(v.wordCount()) + " words, k=" + std::to_string(v.branching()) +
               " L=" + std::to_string(v.depth()) + ", " + std::to_string(v.bits()) + " bits, " +
               (v.masked() ? "masked" : "plain") + ">";
      });
}

}  // namespace mdbrief::python
