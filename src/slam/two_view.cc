#include "ocg/slam/two_view.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

constexpr int kSampleSize = 8;
constexpr double kRadiansToDegrees = 180.0 / M_PI;

// Translates the points to their centroid and scales them to unit mean absolute
// deviation per axis, which conditions the linear systems (Hartley normalization).
Eigen::Matrix3d Normalize(const std::vector<Eigen::Vector2d>& points,
                          std::vector<Eigen::Vector2d>* normalized) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Vector2d deviation = Eigen::Vector2d::Zero();
  for (const auto& p : points) deviation += (p - mean).cwiseAbs();
  deviation /= static_cast<double>(points.size());
  const Eigen::Vector2d scale(deviation.x() > 0 ? 1.0 / deviation.x() : 1.0,
                              deviation.y() > 0 ? 1.0 / deviation.y() : 1.0);
  normalized->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    (*normalized)[i] = (points[i] - mean).cwiseProduct(scale);
  }
  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  T(0, 0) = scale.x();
  T(1, 1) = scale.y();
  T(0, 2) = -mean.x() * scale.x();
  T(1, 2) = -mean.y() * scale.y();
  return T;
}

Eigen::Matrix<double, 9, 1> NullVector(const Eigen::MatrixXd& A) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  return svd.matrixV().col(8);
}

Eigen::Vector2d Apply(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}

struct ModelScore {
  double score = 0.0;
  std::vector<bool> inliers;
  int inlier_count = 0;
};

// One direction of one match: within bound it adds score_base - chi2 to the model's
// score and returns true; beyond it the match is an outlier of the model.
bool AddToScore(double chi2, double bound, double score_base, double* score) {
  if (!std::isfinite(chi2) || chi2 > bound) return false;
  *score += score_base - chi2;
  return true;
}

ModelScore ScoreHomography(const Eigen::Matrix3d& H21, const std::vector<Eigen::Vector2d>& p1,
                           const std::vector<Eigen::Vector2d>& p2, const TwoViewOptions& o) {
  ModelScore result;
  result.inliers.assign(p1.size(), false);
  const Eigen::Matrix3d H12 = H21.inverse();
  const double inverse_sigma2 = 1.0 / (o.sigma * o.sigma);
  for (std::size_t i = 0; i < p1.size(); ++i) {
    const double chi21 = (Apply(H21, p1[i]) - p2[i]).squaredNorm() * inverse_sigma2;
    const double chi12 = (Apply(H12, p2[i]) - p1[i]).squaredNorm() * inverse_sigma2;
    // Both directions count towards the score even when the other one fails.
    const bool forward = AddToScore(chi21, o.chi2_two_dof, o.chi2_two_dof, &result.score);
    const bool backward = AddToScore(chi12, o.chi2_two_dof, o.chi2_two_dof, &result.score);
    result.inliers[i] = forward && backward;
    result.inlier_count += result.inliers[i] ? 1 : 0;
  }
  return result;
}

ModelScore ScoreFundamental(const Eigen::Matrix3d& F21, const std::vector<Eigen::Vector2d>& p1,
                            const std::vector<Eigen::Vector2d>& p2, const TwoViewOptions& o) {
  ModelScore result;
  result.inliers.assign(p1.size(), false);
  const double inverse_sigma2 = 1.0 / (o.sigma * o.sigma);
  auto chi2_to_line = [&](const Eigen::Vector3d& line, const Eigen::Vector2d& p) {
    const double distance = line.dot(p.homogeneous());
    return distance * distance / line.head<2>().squaredNorm() * inverse_sigma2;
  };
  for (std::size_t i = 0; i < p1.size(); ++i) {
    const double chi2 = chi2_to_line(F21 * p1[i].homogeneous(), p2[i]);
    const double chi1 = chi2_to_line(F21.transpose() * p2[i].homogeneous(), p1[i]);
    const bool forward = AddToScore(chi2, o.chi2_one_dof, o.chi2_two_dof, &result.score);
    const bool backward = AddToScore(chi1, o.chi2_one_dof, o.chi2_two_dof, &result.score);
    result.inliers[i] = forward && backward;
    result.inlier_count += result.inliers[i] ? 1 : 0;
  }
  return result;
}

// Triangulates the inliers under one candidate pose and counts those in front of both
// cameras, with a small reprojection error (and parallax, when it is large enough to
// tell front from back).
struct PoseCheck {
  int good = 0;
  std::vector<Eigen::Vector3d> points;
  std::vector<bool> triangulated;
  double parallax_degrees = 0.0;
};

PoseCheck CheckPose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                    const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2,
                    const std::vector<bool>& inliers, const Eigen::Matrix3d& K,
                    const TwoViewOptions& o) {
  PoseCheck check;
  check.points.assign(p1.size(), Eigen::Vector3d::Zero());
  check.triangulated.assign(p1.size(), false);
  Eigen::Matrix<double, 3, 4> P1 = Eigen::Matrix<double, 3, 4>::Zero();
  P1.leftCols<3>() = K;
  Eigen::Matrix<double, 3, 4> P2;
  P2.leftCols<3>() = K * R;
  P2.col(3) = K * t;
  const Eigen::Vector3d centre2 = -R.transpose() * t;
  const double max_error2 = 4.0 * o.sigma * o.sigma;
  std::vector<double> cos_parallaxes;
  for (std::size_t i = 0; i < p1.size(); ++i) {
    if (!inliers[i]) continue;
    const Eigen::Vector3d X = TriangulateLinear(p1[i], p2[i], P1, P2);
    if (!X.allFinite()) continue;
    const Eigen::Vector3d ray1 = X;
    const Eigen::Vector3d ray2 = X - centre2;
    const double cos_parallax = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
    const Eigen::Vector3d X2 = R * X + t;
    // Points at (nearly) infinite depth have no reliable sign; they still count when
    // they project well, as ORB-SLAM2 does.
    const bool distinct = cos_parallax < 0.99998;
    if (distinct && (X.z() <= 0.0 || X2.z() <= 0.0)) continue;
    const double error1 = ((K * X).hnormalized() - p1[i]).squaredNorm();
    const double error2 = ((K * X2).hnormalized() - p2[i]).squaredNorm();
    if (error1 > max_error2 || error2 > max_error2) continue;
    ++check.good;
    cos_parallaxes.push_back(cos_parallax);
    if (distinct) {
      check.points[i] = X;
      check.triangulated[i] = true;
    }
  }
  if (!cos_parallaxes.empty()) {
    // The 50th largest parallax (smallest cosine first): a handful of wrong matches with a
    // huge parallax cannot pass the check alone. Not the 50th smallest: under forward
    // motion the points near the focus of expansion have no parallax however far the
    // camera moves, so that figure stays near zero and the views would never qualify.
    std::sort(cos_parallaxes.begin(), cos_parallaxes.end());
    const std::size_t index = std::min<std::size_t>(50, cos_parallaxes.size() - 1);
    check.parallax_degrees =
        std::acos(std::clamp(cos_parallaxes[index], -1.0, 1.0)) * kRadiansToDegrees;
  }
  return check;
}

// Picks the candidate pose with the most good points; fills result or its failure.
void ChooseAmong(const std::vector<std::pair<Eigen::Matrix3d, Eigen::Vector3d>>& candidates,
                 const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2,
                 const ModelScore& model, const Eigen::Matrix3d& K, const TwoViewOptions& o,
                 double max_ambiguity, TwoViewResult* result) {
  if (candidates.empty()) {
    result->failure = "the model has no decomposition with a translation (pure rotation?)";
    return;
  }
  std::vector<PoseCheck> checks;
  for (const auto& [R, t] : candidates)
    checks.push_back(CheckPose(R, t, p1, p2, model.inliers, K, o));
  std::size_t best = 0;
  for (std::size_t i = 1; i < checks.size(); ++i) {
    if (checks[i].good > checks[best].good) best = i;
  }
  int second = 0;
  for (std::size_t i = 0; i < checks.size(); ++i) {
    if (i != best) second = std::max(second, checks[i].good);
  }
  const int best_good = checks[best].good;
  const int needed = std::max(
      o.min_triangulated, static_cast<int>(std::ceil(o.min_good_fraction * model.inlier_count)));
  result->inliers = model.inlier_count;
  result->parallax_degrees = checks[best].parallax_degrees;
  if (best_good < needed) {
    result->failure = "too few points triangulate well (" + std::to_string(best_good) + " of " +
                      std::to_string(model.inlier_count) + " inliers, need " +
                      std::to_string(needed) + ")";
    return;
  }
  if (second > max_ambiguity * best_good) {
    result->failure = "two poses explain the views about equally well (" +
                      std::to_string(best_good) + " vs " + std::to_string(second) + " points)";
    return;
  }
  const double turned_degrees =
      Eigen::AngleAxisd(candidates[best].first).angle() * kRadiansToDegrees;
  const double min_parallax = turned_degrees > o.turning_degrees
                                  ? std::max(o.min_parallax_degrees, o.min_parallax_turning_degrees)
                                  : o.min_parallax_degrees;
  if (checks[best].parallax_degrees < min_parallax) {
    result->failure =
        "too little parallax (" + std::to_string(checks[best].parallax_degrees) + " degrees)";
    return;
  }
  Eigen::Vector3d t = candidates[best].second;
  const double length = t.norm();
  result->success = true;
  result->T_21 = SE3(candidates[best].first, t / length);
  result->points = checks[best].points;
  for (auto& X : result->points) X /= length;
  result->triangulated = checks[best].triangulated;
  result->triangulated_count =
      static_cast<int>(std::count(result->triangulated.begin(), result->triangulated.end(), true));
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) R = -R;
  return R;
}

}  // namespace

void TwoViewOptions::Check() const {
  CheckOptionFields(*this);
  RequireOption(chi2_two_dof >= chi2_one_dof, "Initializer.chi2TwoDof",
                "must be at least Initializer.chi2OneDof");
}

void ReadSettings(const SettingsFile& file, TwoViewOptions* options) {
  ReadOptionFields(file, options);
}

Eigen::Matrix3d HomographyFromPoints(const std::vector<Eigen::Vector2d>& p1,
                                     const std::vector<Eigen::Vector2d>& p2) {
  const std::size_t n = p1.size();
  Eigen::MatrixXd A(2 * n, 9);
  for (std::size_t i = 0; i < n; ++i) {
    const double u1 = p1[i].x(), v1 = p1[i].y(), u2 = p2[i].x(), v2 = p2[i].y();
    A.row(static_cast<Eigen::Index>(2 * i)) << 0, 0, 0, -u1, -v1, -1, v2 * u1, v2 * v1, v2;
    A.row(static_cast<Eigen::Index>(2 * i + 1)) << u1, v1, 1, 0, 0, 0, -u2 * u1, -u2 * v1, -u2;
  }
  const Eigen::Matrix<double, 9, 1> h = NullVector(A);
  Eigen::Matrix3d H;
  H << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  return H;
}

Eigen::Matrix3d FundamentalFromPoints(const std::vector<Eigen::Vector2d>& p1,
                                      const std::vector<Eigen::Vector2d>& p2) {
  const std::size_t n = p1.size();
  Eigen::MatrixXd A(static_cast<Eigen::Index>(std::max<std::size_t>(n, 9)), 9);
  A.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    const double u1 = p1[i].x(), v1 = p1[i].y(), u2 = p2[i].x(), v2 = p2[i].y();
    A.row(static_cast<Eigen::Index>(i)) << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
  }
  const Eigen::Matrix<double, 9, 1> f = NullVector(A);
  Eigen::Matrix3d F;
  F << f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8);
  // A fundamental matrix has rank 2: zero the smallest singular value.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d singular = svd.singularValues();
  singular(2) = 0.0;
  return svd.matrixU() * singular.asDiagonal() * svd.matrixV().transpose();
}

Eigen::Vector3d TriangulateLinear(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                                  const Eigen::Matrix<double, 3, 4>& P1,
                                  const Eigen::Matrix<double, 3, 4>& P2) {
  Eigen::Matrix4d A;
  A.row(0) = p1.x() * P1.row(2) - P1.row(0);
  A.row(1) = p1.y() * P1.row(2) - P1.row(1);
  A.row(2) = p2.x() * P2.row(2) - P2.row(0);
  A.row(3) = p2.y() * P2.row(2) - P2.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  return X.head<3>() / X(3);
}

TwoViewResult ReconstructTwoView(const std::vector<Eigen::Vector2d>& pixels1,
                                 const std::vector<Eigen::Vector2d>& pixels2,
                                 const PinholeCamera& camera, const TwoViewOptions& options) {
  TwoViewResult result;
  const std::size_t n = pixels1.size();
  if (n != pixels2.size() || n < static_cast<std::size_t>(kSampleSize)) {
    result.failure = "need at least 8 correspondences (got " + std::to_string(n) + ")";
    return result;
  }
  std::vector<Eigen::Vector2d> n1, n2;
  const Eigen::Matrix3d T1 = Normalize(pixels1, &n1);
  const Eigen::Matrix3d T2 = Normalize(pixels2, &n2);
  // The same samples serve both models, so that their scores compare like for like.
  std::mt19937_64 rng(options.seed);
  std::vector<std::size_t> indices(n);
  ModelScore best_h, best_f;
  Eigen::Matrix3d H21 = Eigen::Matrix3d::Identity(), F21 = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Vector2d> s1(kSampleSize), s2(kSampleSize);
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    for (std::size_t i = 0; i < n; ++i) indices[i] = i;
    for (int k = 0; k < kSampleSize; ++k) {
      std::uniform_int_distribution<std::size_t> pick(static_cast<std::size_t>(k), n - 1);
      std::swap(indices[static_cast<std::size_t>(k)], indices[pick(rng)]);
      s1[static_cast<std::size_t>(k)] = n1[indices[static_cast<std::size_t>(k)]];
      s2[static_cast<std::size_t>(k)] = n2[indices[static_cast<std::size_t>(k)]];
    }
    const Eigen::Matrix3d H = T2.inverse() * HomographyFromPoints(s1, s2) * T1;
    ModelScore h = ScoreHomography(H, pixels1, pixels2, options);
    if (h.score > best_h.score) {
      best_h = std::move(h);
      H21 = H;
    }
    const Eigen::Matrix3d F = T2.transpose() * FundamentalFromPoints(s1, s2) * T1;
    ModelScore f = ScoreFundamental(F, pixels1, pixels2, options);
    if (f.score > best_f.score) {
      best_f = std::move(f);
      F21 = F;
    }
  }
  // Refit each model on all its inliers: the best 8-point sample is only as accurate as
  // its 8 noisy points. Keep the refit when it scores at least as well.
  auto inlier_subset = [&](const ModelScore& model, std::vector<Eigen::Vector2d>* a,
                           std::vector<Eigen::Vector2d>* b) {
    a->clear();
    b->clear();
    for (std::size_t i = 0; i < n; ++i) {
      if (!model.inliers[i]) continue;
      a->push_back(n1[i]);
      b->push_back(n2[i]);
    }
    return a->size() >= static_cast<std::size_t>(kSampleSize);
  };
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector2d> a, b;
    if (!best_h.inliers.empty() && inlier_subset(best_h, &a, &b)) {
      const Eigen::Matrix3d H = T2.inverse() * HomographyFromPoints(a, b) * T1;
      ModelScore h = ScoreHomography(H, pixels1, pixels2, options);
      if (h.score >= best_h.score) {
        best_h = std::move(h);
        H21 = H;
      }
    }
    if (!best_f.inliers.empty() && inlier_subset(best_f, &a, &b)) {
      const Eigen::Matrix3d F = T2.transpose() * FundamentalFromPoints(a, b) * T1;
      ModelScore f = ScoreFundamental(F, pixels1, pixels2, options);
      if (f.score >= best_f.score) {
        best_f = std::move(f);
        F21 = F;
      }
    }
  }
  result.score_homography = best_h.score;
  result.score_fundamental = best_f.score;
  const double total = best_h.score + best_f.score;
  result.homography_ratio = total > 0.0 ? best_h.score / total : 0.0;
  if (total <= 0.0) {
    result.failure = "neither a homography nor a fundamental matrix fits the matches";
    return result;
  }
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = camera.fx;
  K(1, 1) = camera.fy;
  K(0, 2) = camera.cx;
  K(1, 2) = camera.cy;
  std::vector<std::pair<Eigen::Matrix3d, Eigen::Vector3d>> candidates;
  if (result.homography_ratio > options.homography_ratio) {
    result.model = TwoViewModel::kHomography;
    cv::Mat H_cv, K_cv;
    cv::eigen2cv(H21, H_cv);
    cv::eigen2cv(K, K_cv);
    std::vector<cv::Mat> rotations, translations, normals;
    cv::decomposeHomographyMat(H_cv, K_cv, rotations, translations, normals);
    // Of the four decompositions, keep those that put the inliers in front of the plane
    // in both views (at most two survive: the planar two-fold ambiguity).
    std::vector<cv::Point2f> before, after;
    const Eigen::Matrix3d K_inverse = K.inverse();
    for (std::size_t i = 0; i < n; ++i) {
      if (!best_h.inliers[i]) continue;
      const Eigen::Vector2d a = (K_inverse * pixels1[i].homogeneous()).hnormalized();
      const Eigen::Vector2d b = (K_inverse * pixels2[i].homogeneous()).hnormalized();
      before.emplace_back(static_cast<float>(a.x()), static_cast<float>(a.y()));
      after.emplace_back(static_cast<float>(b.x()), static_cast<float>(b.y()));
    }
    std::vector<int> possible;
    cv::filterHomographyDecompByVisibleRefpoints(rotations, normals, before, after, possible);
    if (possible.empty()) {  // noise put a few points on the wrong side: let cheirality decide
      for (std::size_t i = 0; i < rotations.size(); ++i) possible.push_back(static_cast<int>(i));
    }
    for (const int index : possible) {
      const std::size_t i = static_cast<std::size_t>(index);
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      cv::cv2eigen(rotations[i], R);
      cv::cv2eigen(translations[i], t);
      if (t.norm() > 1e-12) candidates.emplace_back(NearestRotation(R), t);
    }
    ChooseAmong(candidates, pixels1, pixels2, best_h, K, options, options.max_ambiguity_homography,
                &result);
  } else {
    result.model = TwoViewModel::kFundamental;
    const Eigen::Matrix3d E = K.transpose() * F21 * K;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d U = svd.matrixU();
    Eigen::Matrix3d V = svd.matrixV();
    if (U.determinant() < 0) U = -U;
    if (V.determinant() < 0) V = -V;
    Eigen::Matrix3d W;
    W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    const Eigen::Matrix3d R1 = U * W * V.transpose();
    const Eigen::Matrix3d R2 = U * W.transpose() * V.transpose();
    const Eigen::Vector3d t = U.col(2).normalized();
    candidates = {{R1, t}, {R1, -t}, {R2, t}, {R2, -t}};
    ChooseAmong(candidates, pixels1, pixels2, best_f, K, options, options.max_ambiguity, &result);
  }
  return result;
}

}  // namespace ocg
