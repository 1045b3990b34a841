#pragma once
// Where a joint reference passes near a singularity, and where it changes IK branch.
//
// Measures (each zero at its singularity, signed by the branch on its side):
//   closed-form arms (ur_ik.hpp, spherical_ik.hpp: ArmMeasures)
//     shoulder  the wrist centre's distance from the plane of axis 1 and the arm's lateral
//               offset (m): joint 1 must turn at v / distance to move the wrist sideways;
//               near below kShoulderShare of the arm's reach (|a2| + |a3|, or |a2| + the forearm);
//     elbow     the sine of the elbow's angle from the stretched (or folded) arm: near below
//               kElbowSine (5.7 deg);
//     wrist     sin(q5), zero with axes 4 and 6 in line: near below kWristSine (5.7 deg);
//   any other chain (numeric IK)
//     jacobian  sigma_min / sigma_max of the Jacobian with its linear rows divided by the arm's
//               length scale L (the distances between consecutive joint axes and to the TCP at
//               q = 0, summed), signed by det J: near below kJacobianRatio, the value this
//               measure takes on average where the shipped arms reach their closed-form
//               thresholds (0.006 to 0.013 over random configurations of either arm).
// A branch change is a sign change of a measure between two samples (a measure within
// kSignDeadband of zero keeps the last sign): the path has crossed that singularity, which no
// continuous motion on one IK branch does.

#include <cstddef>
#include <string_view>
#include <vector>

#include "blendbench/robot/ik.hpp"

namespace blendbench {

enum class SingularityKind { kShoulder, kElbow, kWrist, kJacobian };

// "shoulder", "elbow", "wrist", "jacobian".
std::string_view to_string(SingularityKind kind);

inline constexpr double kShoulderShare = 0.05;
inline constexpr double kElbowSine = 0.1;
inline constexpr double kWristSine = 0.1;
inline constexpr double kJacobianRatio = 0.01;
inline constexpr double kSignDeadband = 1e-9;

// One measure at one configuration: its value (m for the shoulder, else dimensionless; signed)
// and the threshold below which |value| counts as near the singularity.
struct SingularityMeasure {
  SingularityKind kind = SingularityKind::kJacobian;
  double value = 0;
  double threshold = 0;
};

// The measures of the solver's chain at link angles q (rad): shoulder, elbow, wrist for the
// closed forms, jacobian for the numeric solver.
std::vector<SingularityMeasure> singularity_measures(const IkSolver& ik, const JointVector& q);

// One stretch of the reference within a measure's threshold: from t_start to t_end (s, sample
// times index * dt), with its closest approach at t (the smallest |value|), the TCP pose there
// and that |value| (`measure`).
struct SingularityPassage {
  SingularityKind kind = SingularityKind::kJacobian;
  double t = 0, t_start = 0, t_end = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double measure = 0;
  double threshold = 0;
};

// One sign change of a measure between samples index - 1 and index: the time index * dt (s),
// the TCP pose there, and the measure's values on both sides.
struct BranchChange {
  SingularityKind kind = SingularityKind::kJacobian;
  std::size_t index = 0;
  double t = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double before = 0, after = 0;
};

// Every passage near a singularity of the joint reference q (samples dt s apart), in time order.
std::vector<SingularityPassage> scan_singularities(const IkSolver& ik, const std::vector<JointVector>& q, double dt);

// Every branch change of q, in time order.
std::vector<BranchChange> branch_changes(const IkSolver& ik, const std::vector<JointVector>& q, double dt);

}  // namespace blendbench
