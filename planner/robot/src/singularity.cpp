#include "blendbench/robot/singularity.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "dh_frames.hpp"

namespace blendbench {
namespace {

// The length scale L of a chain (m): the distances between consecutive joint axis points and
// from the last to the TCP at q = 0, summed (at least 1 mm, so the scaling is finite).
double length_scale(const KinematicChain& chain) {
  const dh::AxisLines lines = dh::axis_lines(chain, [](const std::string&) {});
  double sum = 0;
  for (std::size_t i = 1; i < 6; ++i) sum += (lines.p[i] - lines.p[i - 1]).norm();
  sum += (lines.tcp0.translation() - lines.p[5]).norm();
  return std::max(sum, 1e-3);
}

// The measures with a precomputed length scale (singularity_measures computes it each call).
std::vector<SingularityMeasure> measures_at(const IkSolver& ik, const JointVector& q, double scale) {
  const auto arm = [](const ArmMeasures& m, double reach) {
    return std::vector<SingularityMeasure>{{SingularityKind::kShoulder, m.shoulder, kShoulderShare * reach},
                                           {SingularityKind::kElbow, m.elbow, kElbowSine},
                                           {SingularityKind::kWrist, m.wrist, kWristSine}};
  };
  const JointVector theta = ik.placement().theta(q);
  switch (ik.method()) {
    case IkMethod::kUrClosedForm: {
      const UrGeometry& g = ik.geometry();
      return arm(ur_measures(g, theta), std::abs(g.a2) + std::abs(g.a3));
    }
    case IkMethod::kSphericalWristClosedForm: {
      const SphericalWristGeometry& g = ik.spherical_geometry();
      return arm(spherical_measures(g, theta), std::abs(g.a2) + std::hypot(g.a3, g.d4));
    }
    default: break;
  }
  // the scaled Jacobian's inverse condition number, signed by its determinant
  Mat6 jac = jacobian(ik.chain(), q);
  jac.topRows<3>() /= scale;
  const Eigen::JacobiSVD<Mat6> svd(jac);
  const double ratio = svd.singularValues()[5] / std::max(svd.singularValues()[0], std::numeric_limits<double>::min());
  const double sign = jac.determinant() < 0 ? -1.0 : 1.0;
  return {{SingularityKind::kJacobian, sign * ratio, kJacobianRatio}};
}

Eigen::Isometry3d pose_at(const IkSolver& ik, const JointVector& q) { return forward_kinematics(ik.chain(), q); }

}  // namespace

std::string_view to_string(SingularityKind kind) {
  switch (kind) {
    case SingularityKind::kShoulder: return "shoulder";
    case SingularityKind::kElbow: return "elbow";
    case SingularityKind::kWrist: return "wrist";
    case SingularityKind::kJacobian: return "jacobian";
  }
  return "?";
}

std::vector<SingularityMeasure> singularity_measures(const IkSolver& ik, const JointVector& q) {
  return measures_at(ik, q, length_scale(ik.chain()));
}

std::vector<SingularityPassage> scan_singularities(const IkSolver& ik, const std::vector<JointVector>& q, double dt) {
  std::vector<SingularityPassage> out;
  if (q.empty()) return out;
  const double scale = length_scale(ik.chain());
  // one open passage per measure while the reference stays within its threshold
  std::vector<SingularityPassage> open;
  std::vector<bool> inside;
  std::vector<std::size_t> closest;
  const auto close = [&](std::size_t m) {
    open[m].pose = pose_at(ik, q[closest[m]]);
    out.push_back(open[m]);
    inside[m] = false;
  };
  for (std::size_t k = 0; k < q.size(); ++k) {
    const std::vector<SingularityMeasure> measures = measures_at(ik, q[k], scale);
    if (open.empty()) {
      open.resize(measures.size());
      inside.assign(measures.size(), false);
      closest.assign(measures.size(), 0);
    }
    const double t = static_cast<double>(k) * dt;
    for (std::size_t m = 0; m < measures.size(); ++m) {
      const double value = std::abs(measures[m].value);
      const bool near = value < measures[m].threshold;
      if (near && !inside[m]) {
        open[m] = SingularityPassage{measures[m].kind, t, t, t, Eigen::Isometry3d::Identity(), value, measures[m].threshold};
        inside[m] = true;
        closest[m] = k;
      } else if (near) {
        open[m].t_end = t;
        if (value < open[m].measure) {
          open[m].measure = value;
          open[m].t = t;
          closest[m] = k;
        }
      } else if (inside[m]) {
        close(m);
      }
    }
  }
  for (std::size_t m = 0; m < open.size(); ++m) {
    if (inside[m]) close(m);
  }
  std::stable_sort(out.begin(), out.end(), [](const SingularityPassage& a, const SingularityPassage& b) { return a.t_start < b.t_start; });
  return out;
}

std::vector<BranchChange> branch_changes(const IkSolver& ik, const std::vector<JointVector>& q, double dt) {
  std::vector<BranchChange> out;
  if (q.empty()) return out;
  const double scale = length_scale(ik.chain());
  // the last sign seen outside the deadband, and the value it was seen with
  std::vector<double> sign, last;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const std::vector<SingularityMeasure> measures = measures_at(ik, q[k], scale);
    if (sign.empty()) {
      sign.assign(measures.size(), 0.0);
      last.assign(measures.size(), 0.0);
    }
    for (std::size_t m = 0; m < measures.size(); ++m) {
      const double value = measures[m].value;
      if (std::abs(value) <= kSignDeadband * std::max(1.0, measures[m].threshold)) continue;
      const double s = value > 0 ? 1.0 : -1.0;
      if (sign[m] != 0 && s != sign[m]) {
        out.push_back({measures[m].kind, k, static_cast<double>(k) * dt, pose_at(ik, q[k]), last[m], value});
      }
      sign[m] = s;
      last[m] = value;
    }
  }
  return out;
}

}  // namespace blendbench
