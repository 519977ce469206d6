// The method works: a textured plane rendered through the paper's fisheye camera (OCamCalib
// model of configs/cameras/lafida_fisheye0.yaml) at two poses, the same plane points projected
// into both views. Corresponding dBRIEF descriptors must be clearly closer than BRIEF's, and
// mdBRIEF's masked distance closer still.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "scenes/plane_renderer.hpp"
#include "test_data.hpp"

namespace mdbrief {
namespace {

struct View {
  cv::Mat image;
  std::vector<cv::KeyPoint> keypoints;  // class_id = index of the plane point
};

struct Scene {
  CameraPtr camera;
  PlaneScene plane;
  std::vector<cv::Point2d> planePoints;
};

// ORB corners of the texture, as plane points: keypoints with a true match in every view.
Scene makeScene() {
  Scene s;
  s.camera = loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
  const auto doc = testing::opencvDocDataDir();
  if (!doc) return s;
  s.plane.texture = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  s.plane.texelSize = 0.004;  // 800 texels = 3.2 plane units; the camera is 1 unit away
  std::vector<cv::KeyPoint> corners;
  cv::ORB::create(400)->detect(s.plane.texture, corners);
  for (const auto& kp : corners) s.planePoints.push_back(texelToPlane(s.plane, kp.pt));
  return s;
}

View render(const Scene& s, const CameraPose& pose) {
  View v;
  v.image = renderPlane(*s.camera, pose, s.plane);
  for (size_t i = 0; i < s.planePoints.size(); ++i) {
    cv::Point2d px;
    if (projectPlanePoint(*s.camera, pose, s.planePoints[i], px) && s.camera->isValid(px))
      v.keypoints.emplace_back(cv::Point2f(px), 31.f, -1.f, 1.f, 0, static_cast<int>(i));
  }
  return v;
}

// Per plane point described in both views: the (masked) Hamming distance between its two
// descriptors, as a fraction of the descriptor length.
std::map<int, double> distances(const Scene& s, const View& a, const View& b, DescriptorKind kind,
                                DistortionForm form) {
  DescriptorOptions o;
  o.kind = kind;
  o.form = form;
  o.useOrientation = false;  // the poses barely rotate the plane about the view direction
  const DescriptorExtractor ex(s.camera, o);
  auto ka = a.keypoints, kb = b.keypoints;
  cv::Mat da, db, ma, mb;
  ex.compute(a.image, ka, da, ma);
  ex.compute(b.image, kb, db, mb);
  std::map<int, int> rowOfB;
  for (size_t j = 0; j < kb.size(); ++j) rowOfB[kb[j].class_id] = static_cast<int>(j);
  std::map<int, double> out;
  for (size_t i = 0; i < ka.size(); ++i) {
    const auto it = rowOfB.find(ka[i].class_id);
    if (it == rowOfB.end()) continue;
    const int r = static_cast<int>(i), j = it->second;
    const double d = kind == DescriptorKind::MdBrief ? maskedHammingDistance(da.row(r), ma.row(r), db.row(j), mb.row(j))
                                                     : cv::norm(da.row(r), db.row(j), cv::NORM_HAMMING);
    out[ka[i].class_id] = d / o.bits;
  }
  return out;
}

TEST(FisheyeSynthetic, DistortionAwareTestsKeepCorrespondingDescriptorsClose) {
  const Scene s = makeScene();
  if (s.plane.texture.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed (scripts/setup-deps.sh)");
  // View 1 faces the plane; view 2 is moved sideways and tilted, so the centre of view 1 is
  // seen about 55 degrees off-axis, near the rim of the image circle.
  CameraPose p1, p2;
  p2.centre = {1.1, 0.35, -1.0};
  p2.rotation = cv::Matx33d(std::cos(0.2), 0, -std::sin(0.2), 0, 1, 0, std::sin(0.2), 0, std::cos(0.2));
  const View v1 = render(s, p1), v2 = render(s, p2);

  const std::map<int, double> d[5] = {
      distances(s, v1, v2, DescriptorKind::Brief, DistortionForm::Paper),
      distances(s, v1, v2, DescriptorKind::DBrief, DistortionForm::Paper),
      distances(s, v1, v2, DescriptorKind::DBrief, DistortionForm::Affine),
      distances(s, v1, v2, DescriptorKind::MdBrief, DistortionForm::Paper),
      distances(s, v1, v2, DescriptorKind::MdBrief, DistortionForm::Affine)};
  // Compare on the plane points every variant could describe in both views.
  double mean[5] = {0, 0, 0, 0, 0};
  int pairs = 0;
  for (const auto& [id, unused] : d[0]) {
    if (!d[1].count(id) || !d[2].count(id) || !d[3].count(id) || !d[4].count(id)) continue;
    for (int k = 0; k < 5; ++k) mean[k] += d[k].at(id);
    ++pairs;
  }
  ASSERT_GT(pairs, 100);
  for (double& m : mean) m /= pairs;
  std::printf("%d common pairs; mean distance / bits: BRIEF %.3f, dBRIEF paper %.3f, dBRIEF affine %.3f, "
              "mdBRIEF paper %.3f, mdBRIEF affine %.3f\n",
              pairs, mean[0], mean[1], mean[2], mean[3], mean[4]);
  const double brief = mean[0], paper = mean[1], affine = mean[2], mdPaper = mean[3], mdAffine = mean[4];
  EXPECT_LT(paper, 0.75 * brief);
  EXPECT_LT(affine, 0.95 * brief);
  EXPECT_LT(mdPaper, 0.85 * paper);
  EXPECT_LT(mdAffine, 0.85 * affine);
}

}  // namespace
}  // namespace mdbrief
