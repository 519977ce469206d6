// mdbrief.Database: an image database with an inverted index (database.hpp): add images, query
// the most similar ones (L1 score), save and load.
#include "bindings.hpp"
#include "bow_conversions.hpp"
#include "conversions.hpp"
#include "mdbrief/recognition/database.hpp"
#include "mdbrief/base/file_format_error.hpp"

namespace mdbrief::python {
namespace {

// The bag of words of descriptors, computed without the GIL: the Vocabulary is immutable. The
// Database itself is only touched with the GIL held, since add() must not run alongside anything
// else on it and Python threads may share one.
BowVector bowOf(const Database& db, const py::handle& descriptors, const py::handle& masks) {
  py::object keepD, keepM;
  const cv::Mat d = descriptorsFromArray(descriptors, "descriptors", keepD);
  cv::Mat mk;
  if (!masks.is_none()) mk = descriptorsFromArray(masks, "masks", keepM);
  py::gil_scoped_release release;
  return db.vocabulary().transform(d, mk).bow;
}

py::list resultsToPython(const std::vector<QueryResult>& results) {
  py::list out;
  for (const auto& r : results) out.append(py::make_tuple(r.entry, r.score));
  return out;
}

}  // namespace

void bindDatabase(py::module_& m) {
  boundClass<Database>(m, "Database", R"doc(
Images of a place-recognition database as bags of words of one Vocabulary, with an inverted
index; query returns the entries of highest L1 score. Entry ids are the order of adding, from 0.)doc")
      .def(py::init<Vocabulary>(), py::arg("vocabulary"))
      .def(
          "add",
          [](Database& db, const py::handle& descriptors, const py::handle& masks) {
            return db.add(bowOf(db, descriptors, masks));
          },
          py::arg("descriptors"), py::arg("masks") = py::none(),
          "Adds one image from its descriptors and masks (as Vocabulary.transform takes them); returns its entry id.")
      .def(
          "add_bow", [](Database& db, const py::handle& bow) { return db.add(bowFromPython(bow, "bow")); },
          py::arg("bow"),
          "Adds one image from its bag of words {word: value} (Vocabulary.transform's bow); returns its entry id. "
          "ValueError for a word outside the vocabulary or a value that is not finite and > 0.")
      .def(
          "query",
          [](const Database& db, const py::handle& descriptors, const py::handle& masks, const py::int_& maxResults) {
            return resultsToPython(db.query(bowOf(db, descriptors, masks), saturatedInt(maxResults)));
          },
          py::arg("descriptors"), py::arg("masks") = py::none(), py::kw_only(), py::arg("max_results") = 5, R"doc(
The at most max_results entries most similar to the image of these descriptors and masks, as a
list of (entry, score) tuples, best first (equal scores: lower entry first); entries without a
word in common are not returned. score is the L1 score in (0, 1].)doc")
      .def(
          "query_bow",
          [](const Database& db, const py::handle& bow, const py::int_& maxResults) {
            return resultsToPython(db.query(bowFromPython(bow, "bow"), saturatedInt(maxResults)));
          },
          py::arg("bow"), py::kw_only(), py::arg("max_results") = 5, "query from a bag of words {word: value}.")
      .def(
          "entry", [](const Database& db, int64_t id) {
            if (id < 0 || static_cast<uint64_t>(id) >= db.size())
              throw py::index_error("entry " + std::to_string(id) + " is not below the database's size " +
                                    std::to_string(db.size()));
            return bowToPython(db.entry(static_cast<uint32_t>(id)));
          },
          py::arg("id"), "The bag of words of an entry.")
      .def("__len__", &Database::size)
      .def_property_readonly("vocabulary", &Database::vocabulary)
      .def(
          "save", [](const Database& db, const py::handle& path) { db.save(pathFrom(path, "path")); }, py::arg("path"),
          "Writes the entries and the vocabulary's fingerprint atomically.")
      .def_static(
          "load",
          [](const py::handle& pathArgument, const Vocabulary& vocabulary) {
            const std::string path = pathFrom(pathArgument, "path");
            requireFile(path);
            try {
              return Database::load(path, vocabulary);
            } catch (const FileFormatError& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("path"), py::arg("vocabulary"), R"doc(
Reads a database file saved with this vocabulary. Raises FileNotFoundError for a missing file and
ValueError naming the file and the problem for a bad one, among them a file saved with another
vocabulary.)doc")
      .def("__repr__", [](const Database& db) {
        return "<mdbrief.Database " + std::to_string(db.size()) + " entries, " +
               std::to_string(db.vocabulary().wordCount()) + " words>";
      });
}

}  // namespace mdbrief::python
