#include "planner/path.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <utility>
#include <vector>

namespace blendbench {
namespace {

TEST(Path, PiecesAtAJunctionAreBothNeighboursAndZeroLengthPiecesCount) {
  // three pieces: 1 m, zero length, 2 m
  Path path;
  const auto piece = [](const Vec3& a, const Vec3& b) {
    PathPiece p;
    p.segment = Line{a, b};
    return p;
  };
  path.append(piece(Vec3(0, 0, 0), Vec3(1, 0, 0)));
  path.append(piece(Vec3(1, 0, 0), Vec3(1, 0, 0)));
  path.append(piece(Vec3(1, 0, 0), Vec3(1, 2, 0)));
  const auto touching = [&](double s) {
    std::vector<std::pair<std::size_t, double>> out;
    path.for_pieces_at(s, [&](std::size_t k, double local) { out.emplace_back(k, local); });
    return out;
  };
  using Hits = std::vector<std::pair<std::size_t, double>>;
  EXPECT_EQ(touching(0.5), (Hits{{0, 0.5}}));
  EXPECT_EQ(touching(1.0), (Hits{{0, 1.0}, {1, 0.0}, {2, 0.0}}));
  EXPECT_EQ(touching(2.0), (Hits{{2, 1.0}}));
  EXPECT_EQ(touching(3.0), (Hits{{2, 2.0}}));
  // within the tolerance of a junction, clamped onto each piece
  const auto near = touching(1.0 + 1e-13);
  ASSERT_EQ(near.size(), 3U);
  EXPECT_EQ(near[0].second, 1.0);
  EXPECT_EQ(near[1].second, 0.0);
}

}  // namespace
}  // namespace blendbench
