// cli::StorageReader: reads back what cv::FileStorage writes, in every format, without handing
// YAML or JSON to OpenCV's parser, and names the node and the problem in a malformed file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>
#include <zlib.h>

#include "cli/commands.hpp"
#include "cli/storage_io.hpp"

namespace mdbrief::cli {
namespace {

namespace fs = std::filesystem;

class StorageReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mdbrief_test_storage_" + std::to_string(::getpid()) + "_" + info->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string file(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

 private:
  fs::path dir_;
};

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void expectSameMat(const cv::Mat& a, const cv::Mat& b) {
  ASSERT_EQ(a.type(), b.type());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

TEST_F(StorageReaderTest, ReadsBackWhatFileStorageWritesInEveryFormat) {
  const std::vector<cv::KeyPoint> keypoints{cv::KeyPoint({1.5f, 2.25f}, 31.f, 10.f, 0.5f, 1, -1),
                                            cv::KeyPoint({300.f, 4.f}, 7.5f, -1.f, 0.f, 0, 42)};
  cv::Mat descriptors(2, 32, CV_8U);
  cv::randu(descriptors, 0, 256);
  const cv::Mat matches = (cv::Mat_<double>(2, 3) << 0, 1, 17.5, 1, 0, 3.25);
  const cv::Mat ints = (cv::Mat_<int>(1, 3) << -7, 0, 1 << 30);
  const cv::Mat floats = (cv::Mat_<float>(3, 1) << 0.1f, -2.5f, 1e-7f);
  for (const std::string ext : {".yml", ".yaml", ".json", ".xml", ".yml.gz"}) {
    SCOPED_TRACE(ext);
    const std::string name = path("f" + ext);
    {
      cv::FileStorage storage(name, cv::FileStorage::WRITE);
      cv::write(storage, "keypoints", keypoints);
      storage << "descriptors" << descriptors << "matches" << matches << "ints" << ints << "floats" << floats;
      storage << "empty" << cv::Mat();
    }
    const StorageReader reader(name);
    EXPECT_TRUE(reader.has("keypoints"));
    EXPECT_FALSE(reader.has("masks"));
    const std::vector<cv::KeyPoint> read = reader.keypoints("keypoints");
    ASSERT_EQ(read.size(), keypoints.size());
    for (size_t i = 0; i < read.size(); ++i) {
      EXPECT_EQ(read[i].pt, keypoints[i].pt);
      EXPECT_EQ(read[i].size, keypoints[i].size);
      EXPECT_EQ(read[i].angle, keypoints[i].angle);
      EXPECT_EQ(read[i].response, keypoints[i].response);
      EXPECT_EQ(read[i].octave, keypoints[i].octave);
      EXPECT_EQ(read[i].class_id, keypoints[i].class_id);
    }
    expectSameMat(reader.matrix("descriptors"), descriptors);
    expectSameMat(reader.matrix("matches"), matches);
    expectSameMat(reader.matrix("ints"), ints);
    expectSameMat(reader.matrix("floats"), floats);
    EXPECT_TRUE(reader.matrix("empty").empty());
    EXPECT_TRUE(reader.matrix("masks").empty());
    EXPECT_TRUE(reader.keypoints("masks").empty());
  }
}

// OpenCV before 4.x wrote keypoints as one flat list of 7 numbers each.
TEST_F(StorageReaderTest, ReadsFlatKeypointLists) {
  const StorageReader reader(file("flat.yml", "%YAML:1.0\n---\nkeypoints: [ 392., 243., 31., 10., 1., 0, -1,\n"
                                              "  300.5, 200.25, 37.5, 45., .5, 1, 3 ]\n"));
  const std::vector<cv::KeyPoint> k = reader.keypoints("keypoints");
  ASSERT_EQ(k.size(), 2u);
  EXPECT_EQ(k[1].pt, cv::Point2f(300.5f, 200.25f));
  EXPECT_EQ(k[1].size, 37.5f);
  EXPECT_EQ(k[1].octave, 1);
  EXPECT_EQ(k[1].class_id, 3);
}

// read(reader) must throw an InputError that starts with the file and the node and gives the reason.
template <typename Read>
void expectRefused(const std::string& name, const std::string& node, const std::string& reason, Read read) {
  try {
    read(StorageReader(name));
    ADD_FAILURE() << "accepted: " << readFile(name);
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(name + ": node '" + node + "'", 0), 0u) << what;
    EXPECT_NE(what.find(reason), std::string::npos) << what;
  }
}

TEST_F(StorageReaderTest, MalformedNodesAreInputErrorsNamingFileNodeAndProblem) {
  const std::vector<std::pair<std::string, std::string>> keypointCases{
      {"keypoints: [ [ 1, 2, 3, 4, 5, 6 ] ]", "keypoint 0 has 6 values, not 7"},
      {"keypoints: [ 1, 2, 3, 4, 5, 6, 7, 8 ]", "7 numbers per keypoint, got 8"},
      {"keypoints: [ [ 1, 2, x, 4, 5, 0, -1 ] ]", "'x' is not a number"},
      {"keypoints: [ [ 1, 2, 3, 4, 5, 1.5, -1 ] ]", "1.5 is not an int"},
      {"keypoints: [ [ 1, 2, 3, 4, 5, 0, 1e12 ] ]", "1e12 is not an int"},
      {"keypoints: [ [ 1, 2, [ 3 ], 4, 5, 0, -1 ] ]", "expected a number"},
      {"keypoints: { a: 1 }", "expected a sequence of keypoints"},
      // Issue 45: a keypoint at a NaN position was dropped later without a word.
      {"keypoints: [ [ 1, 2, 3, 4, 5, 0, -1 ], [ .nan, 2, 3, 4, 5, 0, -1 ] ]", "keypoint 1 at (nan, 2)"},
      {"keypoints: [ [ 1, -.inf, 3, 4, 5, 0, -1 ] ]", "keypoint 0 at (1, -inf)"},
      {"keypoints: [ 1, 2, 3, 4, 5, 0, -1, 1, .Nan, 3, 4, 5, 0, -1 ]", "keypoint 1 at (1, nan)"}};
  for (const auto& [text, reason] : keypointCases)
    expectRefused(file("k.yml", text), "keypoints", reason, [](const StorageReader& r) { r.keypoints("keypoints"); });
  const std::vector<std::pair<std::string, std::string>> matrixCases{
      {"m: !!opencv-matrix\n  rows: 2\n  cols: 2\n  dt: u\n  data: [ 1, 2, 3 ]", "rows x cols must be"},
      {"m: !!opencv-matrix\n  rows: -1\n  cols: 0\n  dt: u\n  data: []", "rows x cols must be"},
      {"m: !!opencv-matrix\n  rows: 1\n  cols: 1\n  dt: 3u\n  data: [ 1 ]", "not a single-channel type"},
      {"m: !!opencv-matrix\n  rows: 1\n  cols: 1\n  dt: u\n  data: [ 300 ]", "does not fit dt 'u'"},
      {"m: !!opencv-matrix\n  rows: 1\n  cols: 1\n  dt: i\n  data: [ 0.5 ]", "does not fit dt 'i'"},
      {"m: [ 1, 2 ]", "expected an opencv-matrix"}};
  for (const auto& [text, reason] : matrixCases)
    expectRefused(file("m.yml", text), "m", reason, [](const StorageReader& r) { r.matrix("m"); });
}

TEST_F(StorageReaderTest, FilesThatAreNotFileStorageMapsAreRefusedWhenOpened) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"- 1\n- 2\n", "the top level is not a map"},
      {"keypoints: [ 1, 2\n", "not well-formed YAML/JSON"},
      {std::string("a: 1\0", 5), "byte 4 is NUL"},
      {"a: " + std::string(65, '[') + std::string(65, ']'), "nested deeper than 64"},
      // Issue 45: one of two equal keys was dropped without a word.
      {"{\"keypoints\": [], \"keypoints\": [1]}", "key 'keypoints' appears twice"},
      {"keypoints: []\ndescriptors: 1\nkeypoints: [1]\n", "key 'keypoints' appears twice, on lines 1 and 3"}};
  for (const auto& [text, reason] : cases) {
    const std::string name = file("bad.json", text);
    try {
      StorageReader reader(name);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(StorageReader(path("missing.yml")), InputError);
}

// Issue 45: nesting 1000 levels deep was "bad file" from yaml-cpp, and OpenCV's parsers (XML, and
// YAML or JSON in a .gz) recursed once per level until the stack overflowed. Every format is
// refused past 64 levels before it is parsed, naming the line.
TEST_F(StorageReaderTest, NestingDeeperThanTheLimitIsRefusedBeforeParsingNamingTheLine) {
  const auto refused = [](const std::string& name, const std::string& reason) {
    try {
      StorageReader reader(name);
      ADD_FAILURE() << "accepted: " << name;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  const auto gz = [&](const std::string& name, const std::string& text) {
    gzFile out = gzopen(path(name).c_str(), "wb1");
    gzwrite(out, text.data(), static_cast<unsigned>(text.size()));
    gzclose(out);
    return path(name);
  };
  std::string block = "%YAML:1.0\n---\n", indent;
  for (int i = 0; i < 1000; ++i, indent += ' ') block += indent + "a:\n";
  block += indent + "b: 1\n";
  refused(file("block.yml", block), "nested deeper than 64 levels (line 68)");
  const std::string flow = "{\"a\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  refused(file("flow.json", flow), "nested deeper than 64 levels (line 1)");
  refused(gz("flow.json.gz", flow), "nested deeper than 64 levels (line 1)");
  refused(gz("block.yml.gz", block), "nested deeper than 64 levels (line 68)");
  std::string xml = "<?xml version=\"1.0\"?>\n<opencv_storage>\n<descriptors>";
  for (int i = 0; i < 100000; ++i) xml += "<_>";
  refused(file("deep.xml", xml), "nested deeper than 64 levels (line 3)");
  refused(gz("deep.xml.gz", xml), "nested deeper than 64 levels (line 3)");

  // 64 levels, brackets, '#' and quotes in strings, and comments are read.
  std::string deepest = "%YAML:1.0\n---\n";
  indent.clear();
  for (int i = 0; i < 64; ++i, indent += ' ') deepest += indent + "a:\n";
  deepest += indent + "b: 1\n";
  EXPECT_TRUE(StorageReader(file("deepest.yml", deepest)).has("a"));
  EXPECT_TRUE(StorageReader(gz("deepest.yml.gz", deepest)).has("a"));
  const std::string brackets = "a: \"" + std::string(100, '[') + " # '\"\nb: '" + std::string(100, '{') +
                               " it''s'\n# " + std::string(100, '[') + "\nc: x[y] # ]]\n";
  EXPECT_EQ(StorageReader(file("brackets.yml", brackets)).text("b"), std::string(100, '{') + " it's");
  std::string xmlOk = "<?xml version=\"1.0\"?>\n<opencv_storage>\n<!-- <a><a><a> -->\n<b>1</b>\n<a>";
  for (int i = 0; i < 63; ++i) xmlOk += "<_>";
  xmlOk += "1";
  for (int i = 0; i < 63; ++i) xmlOk += "</_>";
  xmlOk += "</a>\n</opencv_storage>\n";
  EXPECT_TRUE(StorageReader(file("ok.xml", xmlOk)).has("b"));
}

// yaml-cpp took 3.5 GB and 34 s for a 44 MB feature file, and a 10-million-keypoint one ran out
// of memory: text over the parser's limit is refused before it is parsed, naming the limit.
TEST_F(StorageReaderTest, TextOverTheParsersLimitIsRefusedUnparsed) {
  const auto refused = [](const std::string& name, const std::string& reason) {
    try {
      StorageReader reader(name);
      ADD_FAILURE() << "accepted: " << name;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name, 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  // A YAML comment pads the file to exactly the limit (accepted), then one byte more.
  const std::string head = "%YAML:1.0\n---\na: 1\n#";
  std::string text = head + std::string(kMaxYamlCppTextBytes - head.size() - 1, 'x') + "\n";
  ASSERT_EQ(text.size(), kMaxYamlCppTextBytes);
  for (const char* ext : {".yml", ".json"}) {
    EXPECT_TRUE(StorageReader(file(std::string("limit") + ext, text)).has("a")) << ext;
    refused(file(std::string("over") + ext, text + " "), "over the 8 MiB a YAML or JSON file may have");
  }
  // OpenCV's parser: the size of an XML file (a sparse one here), the decompressed text of a .gz.
  const std::string xml = path("over.xml");
  std::ofstream(xml) << "<?xml version=\"1.0\"?>\n<opencv_storage>\n";
  fs::resize_file(xml, kMaxOpenCvTextBytes + 1);
  refused(xml, "over the 256 MiB of text an .xml or .gz file may hold");
  const std::string gz = path("over.yml.gz");
  gzFile out = gzopen(gz.c_str(), "wb1");
  ASSERT_NE(out, nullptr);
  gzputs(out, "%YAML:1.0\n---\na: 1\n#");
  const std::string block(1 << 20, 'x');
  for (std::uintmax_t written = 0; written <= kMaxOpenCvTextBytes; written += block.size())
    ASSERT_EQ(gzwrite(out, block.data(), static_cast<unsigned>(block.size())), static_cast<int>(block.size()));
  gzclose(out);
  ASSERT_LT(fs::file_size(gz), std::uintmax_t{4} << 20);
  refused(gz, "over the 256 MiB of text an .xml or .gz file may hold once decompressed");
}

}  // namespace
}  // namespace mdbrief::cli
