#include "mdbrief/recognition/database.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/framed_file.hpp"

namespace mdbrief {

namespace {

// Body, little-endian, sections at multiples of 8 bytes (framed_file.hpp for the frame):
//   bytes 32-55  u64 vocabulary fingerprint, u32 wordCount, u32 entryCount, u64 postingCount
//   u64 offsets[entryCount + 1] (entry e's words are offsets[e] .. offsets[e+1] - 1),
//   u32 words[postingCount], f32 values[postingCount]
constexpr char kDatabaseMagic[] = "MDBBOWDB";
constexpr uint32_t kDatabaseVersion = 1;
constexpr uint64_t kHeaderEnd = 56;
constexpr uint64_t kMaxDatabaseFileBytes = uint64_t{4} << 30;

inline uint64_t pad8(uint64_t x) { return (x + 7) & ~uint64_t{7}; }

struct Layout {
  uint64_t offsets = 0, words = 0, values = 0, end = 0;
};
Layout layoutOf(uint64_t entries, uint64_t postings) {
  Layout l;
  l.offsets = kHeaderEnd;
  l.words = l.offsets + 8 * (entries + 1);
  l.values = pad8(l.words + 4 * postings);
  l.end = pad8(l.values + 4 * postings);
  return l;
}

// "" when bow is a BowVector of a vocabulary of wordCount words, else the first problem.
std::string bowProblem(const BowVector& bow, size_t wordCount) {
  for (size_t i = 0; i < bow.size(); ++i) {
    if (bow[i].word >= wordCount)
      return "word " + std::to_string(bow[i].word) + " is not below the vocabulary's " + std::to_string(wordCount) +
             " words";
    if (i > 0 && bow[i].word <= bow[i - 1].word) return "words are not ascending and unique";
    if (!std::isfinite(bow[i].value) || !(bow[i].value > 0))
      return "word " + std::to_string(bow[i].word) + " has value " + std::to_string(bow[i].value) +
             " (must be finite and > 0)";
  }
  return "";
}

void requireBow(const BowVector& bow, size_t wordCount, const char* what) {
  if (const std::string p = bowProblem(bow, wordCount); !p.empty())
    throw std::invalid_argument(std::string(what) + ": not a BowVector of this vocabulary: " + p);
}

}  // namespace

Database::Database(Vocabulary vocabulary) : vocabulary_(std::move(vocabulary)), inverted_(vocabulary_.wordCount()) {}

uint32_t Database::add(const BowVector& bow) {
  requireBow(bow, vocabulary_.wordCount(), "Database::add");
  if (entries_.size() >= 0xFFFFFFFFu) throw std::invalid_argument("Database::add: the database is full (2^32 entries)");
  const auto id = static_cast<uint32_t>(entries_.size());
  entries_.push_back(bow);
  for (const BowEntry& e : bow) inverted_[e.word].push_back({id, e.value});
  return id;
}

uint32_t Database::addDescriptors(cv::InputArray descriptors, cv::InputArray masks) {
  return add(vocabulary_.transform(descriptors, masks).bow);
}

std::vector<QueryResult> Database::query(const BowVector& bow, int maxResults) const {
  if (maxResults < 1) throw std::invalid_argument("Database::query: maxResults must be >= 1, got " + std::to_string(maxResults));
  requireBow(bow, vocabulary_.wordCount(), "Database::query");
  // Every entry's sum runs over the common words in ascending order, in double, as l1Score's.
  std::vector<double> score(entries_.size(), 0.0);
  std::vector<uint32_t> touched;
  for (const BowEntry& q : bow)
    for (const Posting& p : inverted_[q.word]) {
      if (score[p.entry] == 0.0) touched.push_back(p.entry);
      score[p.entry] += std::min(q.value, p.value);
    }
  std::vector<QueryResult> results;
  results.reserve(touched.size());
  for (const uint32_t e : touched) results.push_back({e, static_cast<float>(score[e])});
  const auto better = [](const QueryResult& a, const QueryResult& b) {
    return a.score != b.score ? a.score > b.score : a.entry < b.entry;
  };
  const size_t keep = std::min(results.size(), static_cast<size_t>(maxResults));
  std::partial_sort(results.begin(), results.begin() + static_cast<std::ptrdiff_t>(keep), results.end(), better);
  results.resize(keep);
  return results;
}

std::vector<QueryResult> Database::queryDescriptors(cv::InputArray descriptors, cv::InputArray masks, int maxResults) const {
  return query(vocabulary_.transform(descriptors, masks).bow, maxResults);
}

const BowVector& Database::entry(uint32_t id) const {
  if (id >= entries_.size())
    throw std::out_of_range("Database::entry: " + std::to_string(id) + " is not below the " +
                            std::to_string(entries_.size()) + " entries");
  return entries_[id];
}

std::string Database::fileBytes() const {
  uint64_t postings = 0;
  for (const BowVector& b : entries_) postings += b.size();
  const Layout l = layoutOf(entries_.size(), postings);
  std::string body(l.end - internal::kFrameBytes, '\0');
  const auto put = [&](uint64_t at, const void* src, size_t n) {
    if (n) std::memcpy(&body[at - internal::kFrameBytes], src, n);
  };
  const uint64_t fingerprint = vocabulary_.fingerprint();
  const uint32_t counts[2] = {static_cast<uint32_t>(vocabulary_.wordCount()), static_cast<uint32_t>(entries_.size())};
  put(32, &fingerprint, 8);
  put(40, counts, 8);
  put(48, &postings, 8);
  uint64_t offset = 0;
  for (size_t e = 0; e <= entries_.size(); ++e) {
    put(l.offsets + 8 * e, &offset, 8);
    if (e == entries_.size()) break;
    for (const BowEntry& b : entries_[e]) {
      put(l.words + 4 * offset, &b.word, 4);
      put(l.values + 4 * offset, &b.value, 4);
      ++offset;
    }
  }
  return internal::framedFileBytes(kDatabaseMagic, kDatabaseVersion, body);
}

void Database::save(const std::string& path) const { internal::writeFileAtomically(path, fileBytes()); }

Database Database::load(const std::string& path, Vocabulary vocabulary) {
  const internal::FramedFile file =
      internal::readFramedFile(path, kDatabaseMagic, kDatabaseVersion, kMaxDatabaseFileBytes, "database", "");
  const auto fail = [&](const std::string& problem) { return FileFormatError(path, problem); };
  if (file.size < kHeaderEnd) throw fail("truncated: no room for the database header");
  const uint8_t* base = file.bytes();
  uint64_t fingerprint = 0, postings = 0;
  uint32_t wordCount = 0, entryCount = 0;
  std::memcpy(&fingerprint, base + 32, 8);
  std::memcpy(&wordCount, base + 40, 4);
  std::memcpy(&entryCount, base + 44, 4);
  std::memcpy(&postings, base + 48, 8);
  if (fingerprint != vocabulary.fingerprint() || wordCount != vocabulary.wordCount())
    throw fail("made with another vocabulary (its fingerprint or word count differs from the one given)");
  // Bounds before layoutOf's arithmetic: no section can be longer than the file.
  if (postings > file.size / 8) throw fail("the header's " + std::to_string(postings) + " words do not fit in the file");
  const Layout l = layoutOf(entryCount, postings);
  if (l.end != file.size)
    throw fail("the header's sizes (" + std::to_string(entryCount) + " entries, " + std::to_string(postings) +
               " words) need " + std::to_string(l.end) + " bytes, the file has " + std::to_string(file.size));
  Database db(std::move(vocabulary));
  uint64_t previous = 0;
  std::memcpy(&previous, base + l.offsets, 8);
  if (previous != 0) throw fail("entry 0 does not start at word 0");
  for (uint32_t e = 0; e < entryCount; ++e) {
    uint64_t next = 0;
    std::memcpy(&next, base + l.offsets + 8 * (uint64_t{e} + 1), 8);
    if (next < previous || next > postings) throw fail("entry " + std::to_string(e) + ": its words lie outside the file's");
    BowVector bow(static_cast<size_t>(next - previous));
    for (size_t i = 0; i < bow.size(); ++i) {
      std::memcpy(&bow[i].word, base + l.words + 4 * (previous + i), 4);
      std::memcpy(&bow[i].value, base + l.values + 4 * (previous + i), 4);
    }
    if (const std::string p = bowProblem(bow, wordCount); !p.empty())
      throw fail("entry " + std::to_string(e) + ": " + p);
    db.add(bow);
    previous = next;
  }
  if (previous != postings) throw fail("the entries hold " + std::to_string(previous) + " words, the header says " +
                                       std::to_string(postings));
  return db;
}

}  // namespace mdbrief
