#include "blendbench/program/path.hpp"

#include <algorithm>
#include <cassert>

namespace blendbench {

void Path::append(PathPiece piece) {
  assert(pieces_.empty() ||
         (end_point(pieces_.back().segment) - start_point(piece.segment)).norm() <= 1e-9 * std::max(1.0, length()));
  offsets_.push_back(offsets_.back() + blendbench::length(piece.segment));
  pieces_.push_back(std::move(piece));
}

Path::Location Path::locate(double s) const {
  assert(!pieces_.empty());
  s = std::clamp(s, 0.0, length());
  // the last piece whose start is <= s; skip zero-length pieces at the same offset
  const auto it = std::upper_bound(offsets_.begin(), offsets_.end() - 1, s);
  std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - offsets_.begin() - 1, 0));
  k = std::min(k, pieces_.size() - 1);
  // only the last piece can hold s without extending past it: at the path's end, step back
  // over trailing zero-length pieces so the tangent and curvature come from a real piece
  while (k > 0 && offsets_[k + 1] == offsets_[k]) --k;
  return {k, s - offsets_[k]};
}

Vec3 Path::point(double s) const {
  const Location at = locate(s);
  return blendbench::point(pieces_[at.piece].segment, at.s);
}

Vec3 Path::tangent(double s) const {
  const Location at = locate(s);
  return blendbench::tangent(pieces_[at.piece].segment, at.s);
}

Vec3 Path::curvature_vector(double s) const {
  const Location at = locate(s);
  return blendbench::curvature_vector(pieces_[at.piece].segment, at.s);
}

Quat Path::orientation(double s) const {
  if (!oriented()) return Quat::Identity();
  const Location at = locate(s);
  return orientation_at(*pieces_[at.piece].orientation, at.s);
}

Vec3 Path::angular_rate(double s) const {
  if (!oriented()) return Vec3::Zero();
  const Location at = locate(s);
  return angular_rate_at(*pieces_[at.piece].orientation, at.s);
}

}  // namespace blendbench
