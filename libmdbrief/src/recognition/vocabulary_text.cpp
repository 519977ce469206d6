#include "mdbrief/recognition/vocabulary_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "recognition/vocabulary_data.hpp"

namespace mdbrief {

namespace {

// ORBvoc.txt (a million 256-bit words) is 145 MB; a million 512-bit words would be about 600 MB.
constexpr uint64_t kMaxTextBytes = uint64_t{2} << 30;

std::string readText(const std::string& path) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw FileFormatError(path, problem);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw FileFormatError(path, "cannot read its size: " + ec.message());
  if (size > kMaxTextBytes)
    throw FileFormatError(path, "is " + std::to_string(size) + " bytes, more than a text vocabulary may be (" +
                                    std::to_string(kMaxTextBytes) + ")");
  std::ifstream in(path, std::ios::binary);
  std::string text(size, '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size)) || in.gcount() != static_cast<std::streamsize>(size))
    throw FileFormatError(path, "cannot read all of its " + std::to_string(size) + " bytes");
  return text;
}

// The whitespace-separated fields of one line.
class Fields {
 public:
  Fields(const char* begin, const char* end) : p_(begin), end_(end) {}
  bool next(std::string_view& field) {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r')) ++p_;
    if (p_ == end_) return false;
    const char* start = p_;
    while (p_ < end_ && *p_ != ' ' && *p_ != '\t' && *p_ != '\r') ++p_;
    field = std::string_view(start, static_cast<size_t>(p_ - start));
    return true;
  }

 private:
  const char* p_;
  const char* end_;
};

bool parseInt(std::string_view s, long long& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}
bool parseDouble(std::string_view s, double& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::string quoted(std::string_view s) {
  return "'" + std::string(s.substr(0, 32)) + (s.size() > 32 ? "...'" : "'");
}

}  // namespace

Vocabulary importDbow2Text(const std::string& path) {
  const std::string text = readText(path);
  size_t lineNumber = 0;
  const auto fail = [&](const std::string& problem) {
    return FileFormatError(path, "line " + std::to_string(lineNumber) + ": " + problem);
  };
  VocabularyTree tree;
  tree.masked = false;
  std::vector<uint8_t> centroids;
  std::vector<uint8_t> leafFlag{0};
  std::vector<float> nodeWeight{0};
  std::vector<size_t> nodeLine{0};
  tree.childBegin.push_back(0);
  tree.childCount.push_back(0);
  long long previousParent = -1;
  int width = 0;
  bool header = true;
  for (size_t at = 0; at < text.size();) {
    size_t eol = text.find('\n', at);
    if (eol == std::string::npos) eol = text.size();
    ++lineNumber;
    Fields fields(text.data() + at, text.data() + eol);
    at = eol + 1;
    std::string_view f;
    if (header) {
      long long v[4];
      for (int i = 0; i < 4; ++i)
        if (!fields.next(f) || !parseInt(f, v[i]))
          throw fail("expected the header 'k L scoring weighting' (four integers); is this a DBoW2 text vocabulary?");
      if (fields.next(f)) throw fail("the header has more than four fields");
      if (v[0] < 2 || v[0] > kMaxVocabularyBranching)
        throw fail("k = " + std::to_string(v[0]) + " is not in [2, " + std::to_string(kMaxVocabularyBranching) + "]");
      if (v[1] < 1 || v[1] > kMaxVocabularyDepth)
        throw fail("L = " + std::to_string(v[1]) + " is not in [1, " + std::to_string(kMaxVocabularyDepth) + "]");
      if (v[2] < 0 || v[2] > 5) throw fail("scoring " + std::to_string(v[2]) + " is not one of DBoW2's 0..5");
      if (v[3] < 0 || v[3] > 3)
        throw fail("weighting " + std::to_string(v[3]) + " is not one of 0..3 (tf-idf, tf, idf, binary)");
      tree.branching = static_cast<int>(v[0]);
      tree.depth = static_cast<int>(v[1]);
      tree.weighting = static_cast<Weighting>(v[3]);
      header = false;
      continue;
    }
    if (!fields.next(f)) continue;  // a blank line (files often end with one)
    const size_t node = tree.childBegin.size();
    if (node >= 0xFFFFFFF0u) throw fail("more than 2^32 nodes");
    long long parent = 0, leaf = 0;
    if (!parseInt(f, parent)) throw fail("parent " + quoted(f) + " is not an integer");
    if (parent < 0 || static_cast<size_t>(parent) >= node)
      throw fail("parent " + std::to_string(parent) + " of node " + std::to_string(node) +
                 " is not an earlier node (parents come before their children)");
    if (!fields.next(f) || !parseInt(f, leaf) || (leaf != 0 && leaf != 1))
      throw fail("expected the leaf flag (0 or 1) after the parent");
    // The rest: the descriptor's bytes, then the weight.
    std::vector<std::string_view> rest;
    while (fields.next(f)) {
      rest.push_back(f);
      if (rest.size() > 65) throw fail("more than 64 descriptor bytes");
    }
    if (rest.empty()) throw fail("no descriptor bytes and weight");
    const int bytes = static_cast<int>(rest.size()) - 1;
    if (width == 0) {
      if (bytes < 4 || bytes > 64 || bytes % 4)
        throw fail(std::to_string(bytes) + " descriptor bytes: binary descriptors of 4..64 bytes in steps of 4 only");
      width = bytes;
      tree.bits = 8 * width;
      centroids.assign(static_cast<size_t>(width), 0);  // the root's row
    } else if (bytes != width) {
      throw fail(std::to_string(bytes) + " descriptor bytes, the lines before have " + std::to_string(width));
    }
    for (int b = 0; b < bytes; ++b) {
      long long v = 0;
      if (!parseInt(rest[b], v) || v < 0 || v > 255)
        throw fail("descriptor byte " + std::to_string(b + 1) + " " + quoted(rest[b]) +
                   " is not an integer in [0, 255] (binary descriptors only)");
      centroids.push_back(static_cast<uint8_t>(v));
    }
    double weight = 0;
    if (!parseDouble(rest.back(), weight) || !std::isfinite(weight) || weight < 0 || weight > 3.0e38)
      throw fail("weight " + quoted(rest.back()) + " is not a finite number >= 0");
    // Children of one node come on consecutive lines.
    if (parent != previousParent) {
      if (tree.childCount[parent] != 0)
        throw fail("node " + std::to_string(node) + ": the children of node " + std::to_string(parent) +
                   " are not on consecutive lines");
      tree.childBegin[parent] = static_cast<uint32_t>(node);
      previousParent = parent;
    }
    ++tree.childCount[parent];
    tree.childBegin.push_back(0);
    tree.childCount.push_back(0);
    leafFlag.push_back(static_cast<uint8_t>(leaf));
    nodeWeight.push_back(static_cast<float>(weight));
    nodeLine.push_back(lineNumber);
  }
  if (header) throw FileFormatError(path, "empty; expected the header 'k L scoring weighting'");
  const size_t nodes = tree.childBegin.size();
  if (nodes < 2) throw FileFormatError(path, "no nodes after the header");
  for (size_t n = 1; n < nodes; ++n) {
    if (leafFlag[n] != (tree.childCount[n] == 0))
      throw FileFormatError(path, "line " + std::to_string(nodeLine[n]) + ": node " + std::to_string(n) + " is marked " +
                                      (leafFlag[n] ? "a leaf but has children" : "an inner node but has no children"));
    if (leafFlag[n]) tree.wordWeights.push_back(nodeWeight[n]);
  }
  tree.centroids = cv::Mat(static_cast<int>(nodes), width, CV_8UC1, centroids.data());
  try {
    return Vocabulary(vocabularyData(tree));
  } catch (const VocabularyContentError& e) {
    throw FileFormatError(path, e.what());
  }
}

std::string dbow2Text(const Vocabulary& vocabulary) {
  if (vocabulary.masked())
    throw std::invalid_argument("dbow2Text: the vocabulary is masked; the DBoW2 text format has no place for masks");
  const VocabularyTree t = vocabulary.tree();
  const size_t nodes = t.childBegin.size();
  std::vector<uint32_t> parent(nodes, 0);
  for (size_t n = 0; n < nodes; ++n)
    for (uint32_t c = 0; c < t.childCount[n]; ++c) parent[t.childBegin[n] + c] = static_cast<uint32_t>(n);
  std::string out = std::to_string(t.branching) + " " + std::to_string(t.depth) + " 0 " +
                    std::to_string(static_cast<int>(t.weighting)) + "\n";
  out.reserve(nodes * (4 + 4 * static_cast<size_t>(t.centroids.cols)) + out.size());
  size_t word = 0;
  char number[32];
  for (size_t n = 1; n < nodes; ++n) {
    const bool leaf = t.childCount[n] == 0;
    out += std::to_string(parent[n]);
    out += leaf ? " 1" : " 0";
    const uint8_t* row = t.centroids.ptr<uint8_t>(static_cast<int>(n));
    for (int b = 0; b < t.centroids.cols; ++b) {
      out += ' ';
      out += std::to_string(row[b]);
    }
    std::snprintf(number, sizeof number, " %.9g\n", leaf ? static_cast<double>(t.wordWeights[word++]) : 0.0);
    out += number;
  }
  return out;
}

void exportDbow2Text(const Vocabulary& vocabulary, const std::string& path) {
  internal::writeFileAtomically(path, dbow2Text(vocabulary));
}

}  // namespace mdbrief
