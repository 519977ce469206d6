// Patch extraction: patches give the runtime descriptor's bits, patch allocation, image listing,
// skipped images, determinism, and the HDF5 patch file.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/internal/describe/patch_sampling.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "scenes/photo_camera.hpp"
#include "scenes/plane_renderer.hpp"
#include "patchextract/image_digest.hpp"
#include "patchextract/patch_extraction.hpp"
#include "patchextract/patch_sampler.hpp"
#include "patchextract/patch_set.hpp"
#include "test_data.hpp"
#include "write_limits.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using namespace mdbrief::train;

namespace {

using mdbrief::testing::TempDir;

cv::Mat opencvDocImage(const char* name) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  return dir ? cv::imread((*dir / name).string(), cv::IMREAD_GRAYSCALE) : cv::Mat();
}

// compute() keypoint by keypoint against the same tests read from the sampled patch: every
// patch the sampler gives is of a keypoint compute() keeps, with the angle compute() leaves,
// and a test may differ only where rounding to 8 bits made its two values equal. `calibration`
// is what the sampler gets (null: the photo camera, which the extractor must then hold).
void expectPatchesGiveTheRuntimeBits(const DescriptorExtractor& extractor, const Camera* calibration,
                                     const ImagePyramid& pyramid, const std::vector<cv::KeyPoint>& kps) {
  const ComparisonSet& tests = extractor.comparisonSet();
  size_t patches = 0, compared = 0, ties = 0;
  uint8_t patch[kPatchSize * kPatchSize];
  for (const cv::KeyPoint& kp : kps) {
    float angle = -2.f;
    if (!samplePatch(extractor.options(), calibration, pyramid, kp, patch, angle)) continue;
    ++patches;
    std::vector<cv::KeyPoint> one{kp};
    cv::Mat desc;
    extractor.compute(pyramid, one, desc);
    ASSERT_EQ(one.size(), 1u) << "compute() dropped a keypoint whose patch was sampled at " << kp.pt;
    EXPECT_EQ(angle, one[0].angle) << kp.pt;
    for (size_t d = 0; d < tests.tests.size(); ++d) {
      const ComparisonPair& t = tests.tests[d];
      const int v1 = patch[(t.y1 + kPatchHalf) * kPatchSize + t.x1 + kPatchHalf];
      const int v2 = patch[(t.y2 + kPatchHalf) * kPatchSize + t.x2 + kPatchHalf];
      const bool runtime = (desc.at<uint8_t>(0, int(d / 8)) >> (d % 8)) & 1;
      ++compared;
      if (v1 == v2) {
        ++ties;
        continue;
      }
      ASSERT_EQ(v1 < v2, runtime) << "test " << d << " at " << kp.pt;
    }
  }
  EXPECT_GT(patches, 50u);
  EXPECT_LT(double(ties), 0.05 * double(compared)) << "rounding ties are rare";
}

// ORB keypoints of graf1 rendered through the LaFiDa fisheye (empty if opencv-doc is missing).
struct FisheyeScene {
  CameraPtr camera;
  cv::Mat image;
  std::vector<cv::KeyPoint> keypoints;
};

FisheyeScene fisheyeScene() {
  FisheyeScene s;
  const cv::Mat photo = opencvDocImage("graf1.png");
  if (photo.empty()) return s;
  s.camera = loadCamera((mdbrief::testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
  s.image = renderPlane(*s.camera, CameraPose{}, PlaneScene{photo, std::tan(1.0) / 400.0});
  cv::ORB::create(300)->detect(s.image, s.keypoints);
  return s;
}

DescriptorOptions withRandomSet(DescriptorOptions o) {
  o.pattern = "brief_random_512";
  o.bits = 512;
  return o;
}

}  // namespace

TEST(PatchSampler, PerspectivePatchesGiveTheRuntimeBitsThroughThePhotoCamera) {
  const cv::Mat img = opencvDocImage("graf1.png");
  if (img.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  std::vector<cv::KeyPoint> kps;
  cv::ORB::create(300)->detect(img, kps);
  const ImagePyramid pyramid(img, PyramidOptions{});
  // The defaults: mdBRIEF, Affine form, orientation re-measured on the tangent plane.
  const DescriptorExtractor extractor(photoCamera(img.size()), withRandomSet({}));
  expectPatchesGiveTheRuntimeBits(extractor, nullptr, pyramid, kps);
}

TEST(PatchSampler, BriefPatchesNeedNoCameraAndFollowSupportScaleAndNearestSampling) {
  const cv::Mat img = opencvDocImage("graf1.png");
  if (img.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  std::vector<cv::KeyPoint> kps;
  cv::ORB::create(300)->detect(img, kps);
  // Sizes between the levels: footprints at a fractional scale of their level.
  for (auto& kp : kps) kp.size *= 1.37f;
  const ImagePyramid pyramid(img, PyramidOptions{});
  DescriptorOptions o = withRandomSet({});
  o.kind = DescriptorKind::Brief;
  o.supportScale = 1.5;
  expectPatchesGiveTheRuntimeBits(DescriptorExtractor(nullptr, o), nullptr, pyramid, kps);
  o.sampling = Sampling::Nearest;
  expectPatchesGiveTheRuntimeBits(DescriptorExtractor(nullptr, o), nullptr, pyramid, kps);
}

TEST(PatchSampler, FisheyePatchesGiveTheRuntimeBitsInBothForms) {
  const FisheyeScene s = fisheyeScene();
  if (s.image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const ImagePyramid pyramid(s.image, PyramidOptions{});
  expectPatchesGiveTheRuntimeBits(DescriptorExtractor(s.camera, withRandomSet({})), s.camera.get(), pyramid,
                                  s.keypoints);
  // The paper's form with the detector's angle: how the sets were sampled before issue 18.
  DescriptorOptions paper = withRandomSet({});
  paper.form = DistortionForm::Paper;
  paper.orientation = OrientationSource::Keypoint;
  expectPatchesGiveTheRuntimeBits(DescriptorExtractor(s.camera, paper), s.camera.get(), pyramid, s.keypoints);
}

TEST(PatchSampler, RejectsInvalidOptionsAndAMissingCamera) {
  const ImagePyramid pyramid(cv::Mat(64, 64, CV_8UC1, cv::Scalar(7)), PyramidOptions{});
  uint8_t patch[kPatchSize * kPatchSize];
  float angle;
  DescriptorOptions bad;
  bad.orientationRadius = 40;
  EXPECT_THROW(samplePatch(bad, nullptr, pyramid, cv::KeyPoint(32, 32, 31), patch, angle), std::invalid_argument);
  EXPECT_THROW(internal::samplePatch(DescriptorOptions{}, nullptr, pyramid, cv::KeyPoint(32, 32, 31), patch, angle),
               std::invalid_argument);
  // A keypoint whose patch reaches past the image, or without a usable size, gives no patch.
  EXPECT_FALSE(samplePatch(DescriptorOptions{}, nullptr, pyramid, cv::KeyPoint(10, 10, 31), patch, angle));
  EXPECT_FALSE(samplePatch(DescriptorOptions{}, nullptr, pyramid, cv::KeyPoint(32, 32, -1), patch, angle));
  EXPECT_TRUE(samplePatch(DescriptorOptions{}, nullptr, pyramid, cv::KeyPoint(32, 32, 31), patch, angle));
  EXPECT_EQ(patch[0], 7);
}

TEST(PatchAllocation, SharesTheBudgetAsEquallyAsTheImagesAllow) {
  EXPECT_EQ(allocatePatches({100, 100, 100}, 30), (std::vector<size_t>{10, 10, 10}));
  EXPECT_EQ(allocatePatches({100, 2, 100}, 30), (std::vector<size_t>{14, 2, 14}));
  EXPECT_EQ(allocatePatches({5, 0, 3}, 30), (std::vector<size_t>{5, 0, 3}));
  const auto t = allocatePatches({50, 7, 1000, 13, 400}, 301);
  EXPECT_EQ(std::accumulate(t.begin(), t.end(), size_t(0)), 301u);
  EXPECT_EQ(t[1], 7u);
  EXPECT_EQ(t[3], 13u);
  EXPECT_EQ(t[0], 50u);  // 50 < the equal share of 60: all of them
  EXPECT_LE(std::max(t[2], t[4]) - std::min(t[2], t[4]), 1u);
}

// Against values computed apart from the project (Python: FNV-1a 64 from the offset basis
// 1469598103934665603 over the width and height as 4 little-endian bytes each, then the pixels):
// held-out lists, learned sets and vocabularies record these digests.
TEST(ImageDigest, IsTheRecordedFnv1aOfTheSizeAndThePixels) {
  const uint8_t pixels[] = {1, 2, 3, 4, 5, 6};
  EXPECT_EQ(imageDigest(cv::Mat(2, 3, CV_8UC1, const_cast<uint8_t*>(pixels))), "13ca2c450f6cb9ad");
  EXPECT_EQ(imageDigest(cv::Mat(3, 2, CV_8UC1, const_cast<uint8_t*>(pixels))), "fc968c1164ca9ebd");
  // A view into a wider image: its rows, not the bytes between them.
  cv::Mat wide(2, 5, CV_8UC1, cv::Scalar(99));
  cv::Mat(2, 3, CV_8UC1, const_cast<uint8_t*>(pixels)).copyTo(wide.colRange(1, 4));
  EXPECT_EQ(imageDigest(wide.colRange(1, 4)), "13ca2c450f6cb9ad");
}

TEST(ImageListing, FindsNestedImagesAndRejectsBadFolders) {
  TempDir dir("list");
  fs::create_directories(dir.path / "sub");
  cv::imwrite((dir.path / "sub" / "b.PNG").string(), cv::Mat(8, 8, CV_8UC1, cv::Scalar(1)));
  cv::imwrite((dir.path / "a.jpg").string(), cv::Mat(8, 8, CV_8UC1, cv::Scalar(1)));
  std::ofstream(dir.path / "notes.txt") << "x";
  const auto images = listImages({dir.path});
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].filename(), "a.jpg");
  EXPECT_THROW(listImages({dir.path / "missing"}), std::invalid_argument);
  fs::create_directories(dir.path / "empty");
  std::ofstream(dir.path / "empty" / "readme.md") << "x";
  try {
    listImages({dir.path / "empty"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(Extraction, SpreadsOverImagesSkipsBrokenFilesAndIsDeterministic) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  TempDir dir("extract");
  for (const char* f : {"box.png", "box_in_scene.png", "butterfly.jpg"})
    fs::copy_file(*doc / f, dir.path / f);
  std::ofstream(dir.path / "broken.jpg") << "not a jpeg";
  {
    // A truncated JPEG decodes partly: skipped, not trained on.
    std::vector<uchar> jpeg;
    cv::imencode(".jpg", cv::imread((*doc / "box.png").string(), cv::IMREAD_GRAYSCALE), jpeg);
    std::ofstream(dir.path / "cut.jpg", std::ios::binary).write(reinterpret_cast<const char*>(jpeg.data()),
                                                               static_cast<std::streamsize>(jpeg.size() / 2));
  }
  ExtractionOptions o;
  o.imageDirs = {dir.path};
  o.patches = 600;
  o.seed = 7;
  ExtractionReport r1, r2;
  const PatchSet a = extractPatches(o, r1);
  const PatchSet b = extractPatches(o, r2);
  EXPECT_EQ(r1.imagesFound, 5u);
  EXPECT_EQ(r1.imagesUsed, 3u);
  ASSERT_EQ(r1.skipped.size(), 2u);
  EXPECT_EQ(r1.skipped[0].reason, "unreadable");
  EXPECT_NE(r1.skipped[1].reason.find("truncated JPEG"), std::string::npos) << r1.skipped[1].reason;
  ASSERT_EQ(a.count(), 600u);
  EXPECT_EQ(a.pixels, b.pixels);
  std::vector<size_t> perImage(a.images.size(), 0);
  for (const auto& rec : a.records) ++perImage[rec.image];
  for (size_t i = 0; i < a.images.size(); ++i) {
    if (fs::path(a.images[i]).filename() != "broken.jpg" && fs::path(a.images[i]).filename() != "cut.jpg") {
      EXPECT_EQ(perImage[i], 200u) << a.images[i];
    }
  }
  o.seed = 8;
  ExtractionReport r3;
  const PatchSet c = extractPatches(o, r3);
  EXPECT_NE(a.pixels, c.pixels) << "another seed picks other keypoints";
}

TEST(Extraction, KeypointBudgetIsBoundedBeforeAnyImageIsRead) {
  ExtractionOptions o;
  o.imageDirs = {"/nonexistent"};
  for (const int budget : {0, kMaxKeypointsPerImage + 1, std::numeric_limits<int>::max()}) {
    o.keypointsPerImage = budget;
    ExtractionReport r;
    try {
      extractPatches(o, r);
      ADD_FAILURE() << budget << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("keypointsPerImage"), std::string::npos) << e.what();
    }
  }
}

TEST(PatchFile, RoundTripAndBrokenFiles) {
  TempDir dir("h5");
  PatchSet s;
  s.images = {"one.png", "two.png"};
  for (int i = 0; i < 5; ++i) {
    s.records.push_back({i % 2, 1.5f * i, 2.5f * i, 31.f, 10.f * i, 0.1f * i, 0});
    for (int k = 0; k < 1024; ++k) s.pixels.push_back(static_cast<uint8_t>(i * 7 + k));
  }
  s.attributes = {{"detector", "orb"}, {"seed", "3"}};
  const fs::path p = dir.path / "set.h5";
  writePatchSet(s, p);
  const PatchSet r = readPatchSet(p);
  EXPECT_EQ(r.images, s.images);
  EXPECT_EQ(r.pixels, s.pixels);
  ASSERT_EQ(r.count(), 5u);
  EXPECT_FLOAT_EQ(r.records[3].y, 7.5f);
  EXPECT_EQ(r.records[3].image, 1);

  std::ofstream(dir.path / "text.h5") << "hello";
  for (const fs::path& bad : {dir.path / "text.h5", dir.path / "missing.h5"}) {
    try {
      readPatchSet(bad);
      ADD_FAILURE() << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
    }
  }
  // A truncated copy must fail cleanly, never crash.
  const auto size = fs::file_size(p);
  fs::copy_file(p, dir.path / "cut.h5");
  fs::resize_file(dir.path / "cut.h5", size / 2);
  EXPECT_THROW(readPatchSet(dir.path / "cut.h5"), std::runtime_error);
  EXPECT_THROW(writePatchSet(s, dir.path / "nofolder" / "x.h5"), std::runtime_error);
}

// libhdf5 1.10 follows a local heap's free list that loops back until memory runs out (fuzzing
// found one: 24 GB). The reader finds the loop first; the heap's signature inside the data (an
// image named after it) is no reason to refuse a file.
TEST(PatchFile, ALocalHeapFreeListThatLoopsIsRefusedBeforeLibhdf5ReadsIt) {
  TempDir dir("h5_heap");
  PatchSet s;
  s.images = {"HEAP", "HEAP\x01.png"};
  s.records.push_back({1, 1.f, 2.f, 31.f, 0.f, 0.5f, 0});
  s.pixels.assign(1024, 7);
  const fs::path p = dir.path / "set.h5";
  writePatchSet(s, p);
  EXPECT_EQ(readPatchSet(p).images, s.images);

  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // The root group's heap: "HEAP", version 0, three zero bytes, then (8-byte lengths and
  // offsets) the data size, the first free block and the data address.
  const size_t at = bytes.find(std::string("HEAP\0\0\0\0", 8));
  ASSERT_NE(at, std::string::npos);
  uint64_t size = 0, address = 0;
  std::memcpy(&size, &bytes[at + 8], 8);
  std::memcpy(&address, &bytes[at + 24], 8);
  ASSERT_GE(size, 16u);
  ASSERT_LE(address + size, bytes.size());
  const uint64_t first = 0;
  std::memcpy(&bytes[at + 16], &first, 8);       // the free list starts at the data's byte 0
  std::memcpy(&bytes[address], &first, 8);       // whose next block is itself
  const fs::path looped = dir.path / "looped.h5";
  std::ofstream(looped, std::ios::binary) << bytes;
  try {
    readPatchSet(looped);
    ADD_FAILURE() << "a looping free list was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("free list that loops"), std::string::npos) << e.what();
  }
}

// A write that fails (here beyond the file size limit) keeps the previous file, leaves no
// temporary, and leaves libhdf5 nothing it cannot close: the process exits cleanly (it used to
// crash in libhdf5's exit handler).
TEST(PatchFile, AFailedWriteKeepsTheOldFileAndTheProcessExitsCleanly) {
  TempDir dir("h5_fsize");
  const auto patchSet = [](int count) {
    PatchSet s;
    s.images = {"one.png"};
    for (int i = 0; i < count; ++i) {
      s.records.push_back({0, 1.f * i, 2.f * i, 31.f, 0.f, 0.f, 0});
      for (int k = 0; k < 1024; ++k) s.pixels.push_back(static_cast<uint8_t>(i + k));
    }
    return s;
  };
  const fs::path p = dir.path / "set.h5";
  writePatchSet(patchSet(5), p);
  const std::string before = mdbrief::testing::readFile(p);
  EXPECT_EXIT(
      {
        const mdbrief::testing::FileSizeLimit limit(64 * 1024);
        try {
          writePatchSet(patchSet(300), p);
        } catch (const std::runtime_error& e) {
          std::exit(std::string(e.what()).find("File too large") != std::string::npos ? 0 : 3);
        }
        std::exit(4);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_EQ(mdbrief::testing::readFile(p), before);
  EXPECT_EQ(mdbrief::testing::temporaryFiles(dir.path), std::vector<std::string>{});
}

TEST(ViewChange, MapsBothWaysAndIsReproducible) {
  ViewChangeOptions o;
  const cv::Size size(640, 480);
  const auto perspective = randomViewChange(size, nullptr, o, 42);
  const auto again = randomViewChange(size, nullptr, o, 42);
  cv::Point2d v, back, v2;
  ASSERT_TRUE(perspective->toView({320, 240}, v));
  ASSERT_TRUE(again->toView({320, 240}, v2));
  EXPECT_EQ(v, v2);
  ASSERT_TRUE(perspective->toSource(v, back));
  EXPECT_NEAR(cv::norm(back - cv::Point2d(320, 240)), 0.0, 1e-6);
  EXPECT_GT(perspective->localZoom({320, 240}), 1 / o.maxZoom / 1.5);
  // With a camera: a turned and zoomed fisheye lens, round trip through the bearings.
  CameraIntrinsics k{640, 480, 300, 300, 319.5, 239.5};
  const CameraPtr pinhole = std::make_shared<PinholeCamera>(k);
  const auto turned = randomViewChange(size, pinhole, o, 7);
  ASSERT_NE(turned->viewCamera(), nullptr);
  int mapped = 0;
  for (double x = 100; x < 600; x += 50)
    for (double y = 100; y < 400; y += 50)
      if (turned->toView({x, y}, v)) {
        ASSERT_TRUE(turned->toSource(v, back));
        EXPECT_NEAR(cv::norm(back - cv::Point2d(x, y)), 0.0, 1e-6);
        ++mapped;
      }
  EXPECT_GT(mapped, 10);
  const cv::Mat img(size, CV_8UC1, cv::Scalar(100));
  EXPECT_EQ(cv::countNonZero(perspective->render(img, 1) != again->render(img, 1)), 0) << "same seed, same view";
  ViewChangeOptions bad;
  bad.maxZoom = 0.5;
  EXPECT_THROW(randomViewChange(size, nullptr, bad, 1), std::invalid_argument);
}

// A view that shrinks the source low-passes it first: into its own buffer, never the caller's
// image (the extraction samples the reference patches from that image after rendering its views).
TEST(ViewChange, RenderLeavesItsSourceUntouched) {
  const cv::Size size(320, 240);
  cv::Mat source(size, CV_8UC1);
  cv::RNG(5).fill(source, cv::RNG::UNIFORM, 0, 256);
  const cv::Mat before = source.clone();
  int shrinking = 0;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const auto change = randomViewChange(size, nullptr, ViewChangeOptions{}, seed);
    if (!(change->localZoom({size.width / 2.0, size.height / 2.0}) < 0.95)) continue;
    ++shrinking;
    change->render(source, seed);
    ASSERT_EQ(cv::countNonZero(source != before), 0) << "seed " << seed;
  }
  EXPECT_GT(shrinking, 0) << "no shrinking view among the seeds: the test checks nothing";
}

TEST(Extraction, CounterpartsAreTheSameKeypointsInChangedViewsAndHeldOutImagesAreSkipped) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  TempDir dir("pairs");
  for (const char* f : {"graf1.png", "box_in_scene.png", "butterfly.jpg"}) fs::copy_file(*doc / f, dir.path / f);
  ExtractionOptions o;
  o.imageDirs = {dir.path};
  o.patches = 400;
  o.counterparts = 2;
  ExtractionReport r1, r2;
  const PatchSet a = extractPatches(o, r1);
  const PatchSet b = extractPatches(o, r2);
  // graf1.png is Oxford graf img1 under another name: held out by its pixels.
  EXPECT_EQ(r1.heldOut, 1u);
  ASSERT_EQ(a.count(), 400u);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(a.counterpartPixels, b.counterpartPixels);
  ASSERT_GE(a.counterpartCount(), a.count());
  ASSERT_LE(a.counterpartCount(), 2 * a.count());
  EXPECT_TRUE(std::is_sorted(a.counterpartOf.begin(), a.counterpartOf.end()));
  // A counterpart resembles its own reference patch more than another keypoint's.
  double own = 0, other = 0;
  for (size_t j = 0; j < a.counterpartCount(); ++j) {
    const uint8_t* c = a.counterpartPixels.data() + j * 1024;
    const uint8_t* r = a.pixels.data() + a.counterpartOf[j] * 1024;
    const uint8_t* s = a.pixels.data() + ((a.counterpartOf[j] + 97) % a.count()) * 1024;
    for (int i = 0; i < 1024; ++i) own += std::abs(c[i] - r[i]), other += std::abs(c[i] - s[i]);
  }
  EXPECT_LT(own, 0.6 * other);
  EXPECT_EQ(a.usedImageDigests().size(), 2u);
  // The pairs and digests survive the patch file.
  const fs::path file = dir.path / "pairs.h5";
  writePatchSet(a, file);
  const PatchSet c = readPatchSet(file);
  EXPECT_EQ(c.counterpartPixels, a.counterpartPixels);
  EXPECT_EQ(c.counterpartOf, a.counterpartOf);
  EXPECT_EQ(c.imageDigests, a.imageDigests);
}

// Issue 29: mdbrief-patchextract's output may not be one of its held-out lists (under any name).
TEST(PatchSet, AnOutputThatIsAnInputIsRefused) {
  TempDir dir("patchset_same");
  const fs::path list = dir.path / "held_out.txt";
  std::ofstream(list) << "0123456789abcdef img\n";
  fs::create_symlink(list, dir.path / "link.h5");
  try {
    checkPatchSetOutput(dir.path / "link.h5", {dir.path / "other.txt", list});
    ADD_FAILURE() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the same file as the input " + list.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(mdbrief::testing::readFile(list), "0123456789abcdef img\n");
  EXPECT_NO_THROW(checkPatchSetOutput(dir.path / "patches.h5", {list}));
}
