// The tool angles of the G-code reader (gcode_angles.hpp).

#include "gcode_angles.hpp"

#include <array>
#include <cmath>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/units.hpp"
#include "blendbench/robot/kinematics.hpp"

namespace blendbench::gcode_detail {

std::optional<Quat> ToolAngles::apply(const LineWords& lw, bool incremental, int line, const std::string& file) {
  const Word* first = lw.first_of("ABC");
  if (!first) return std::nullopt;
  const auto fail = [&](const Word& w, const std::string& message) { throw InputError(file, line, w.column, w.text, message); };
  const std::array<char, 3> letters = {'A', 'B', 'C'};
  // the angles start unset: the first line gives all three, absolute
  if (!set_) {
    if (incremental) fail(*first, "the first tool angles must be absolute (G90): they start unset, so G91 has nothing to add to");
    for (const char letter : letters) {
      if (lw.get(letter)) continue;
      fail(*first, std::string("the first line with tool angles must give all of A, B and C (they start unset); ") + letter +
                       " is missing");
    }
    set_ = true;
  }
  // modal like X, Y, Z: G91 adds to the angle, an angle not written keeps its value
  for (std::size_t k = 0; k < letters.size(); ++k) {
    const Word* w = lw.get(letters[k]);
    if (!w) continue;
    double& angle = rpy_deg_[static_cast<Eigen::Index>(mapping_.abc[k])];
    const double value = incremental ? angle + w->value : w->value;
    if (!(std::abs(value) <= kMaxToolAngleDeg)) {
      fail(*w, "the tool angle " + std::string(1, letters[k]) + " reaches " + format_value(value, 10) + " degrees, beyond +-" +
                   format_value(kMaxToolAngleDeg, 10));
    }
    angle = value;
  }
  return Quat(rotation_from_rpy(rpy_deg_ * kDeg)).normalized();
}

}  // namespace blendbench::gcode_detail
