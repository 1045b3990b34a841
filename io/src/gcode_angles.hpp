#pragma once
// Private to io/src (not installed): the tool angles of the G-code reader (gcode.hpp, "Tool
// angles"): the modal roll, pitch and yaw that a line's A, B, C words set through the mapping
// GcodeOptions::angles, and the tool orientation they give.

#include <optional>
#include <string>

#include "blendbench/io/gcode.hpp"
#include "gcode_words.hpp"

namespace blendbench::gcode_detail {

class ToolAngles {
 public:
  explicit ToolAngles(const GcodeAngles& mapping) : mapping_(mapping) {}

  // The modal angles updated by the A, B, C words of line `line` (under G91, `incremental`, a
  // word adds its degrees to its angle) and the orientation R = Rz(yaw) Ry(pitch) Rx(roll) they
  // give (unit quaternion, program frame); none when the line has no angle word. The first line
  // with angle words must give all three, absolute. Throws InputError(file, line, column, word,
  // message) at the word that breaks a rule (and for an angle beyond +-kMaxToolAngleDeg).
  std::optional<Quat> apply(const LineWords& lw, bool incremental, int line, const std::string& file);

 private:
  GcodeAngles mapping_;
  bool set_ = false;                  // whether a line has set the angles yet
  Vec3 rpy_deg_ = Vec3::Zero();       // roll, pitch, yaw (degrees)
};

}  // namespace blendbench::gcode_detail
