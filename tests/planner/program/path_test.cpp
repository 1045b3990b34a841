#include "blendbench/program/path.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
// Relative to the path's length: a local s is s less a running sum of lengths, so it may
// pass its piece's end by the rounding of that sum (harmless: every segment query clamps).
constexpr double kSumRounding = 1e-14;

std::string where(std::uint64_t seed, int i) { return test::seed_text(seed) + " case " + std::to_string(i); }

// A piece carrying its index in `move`, so a test can tell the pieces apart.
PathPiece piece_of(Segment segment, int index) {
  PathPiece p;
  p.segment = std::move(segment);
  p.move = index;
  return p;
}

// A random path of 1..8 pieces of every kind, 1 mm .. 1 m across, chained end to start, with
// zero-length pieces (lines, and clothoids that keep a tangent) at random places: first, in
// between, several in a row, last.
Path random_path(std::mt19937_64& rng) {
  Path path;
  Vec3 at = test::random_point(rng);
  const double size = test::log_uniform(rng, 1e-3, 1);
  const auto zero_length = [&] {
    if (test::uniform(rng, 0, 1) < 0.5) return Segment(Line{at, at});
    const Vec3 e1 = test::random_unit(rng);
    return Segment(Clothoid{at, e1, test::random_perpendicular(rng, e1), 1 / size, 1 / (size * size), 0.0});
  };
  const auto maybe_zero_length = [&] {
    while (test::uniform(rng, 0, 1) < 0.3) path.append(piece_of(zero_length(), static_cast<int>(path.pieces().size())));
  };
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 8));
  for (int k = 0; k < n; ++k) {
    maybe_zero_length();
    const auto kind = test::kSegmentKinds[static_cast<std::size_t>(test::uniform(rng, 0, test::kSegmentKinds.size()))];
    path.append(piece_of(test::random_segment(rng, kind, at, size), static_cast<int>(path.pieces().size())));
    at = end_point(path.pieces().back().segment);
  }
  maybe_zero_length();
  return path;
}

// Start offsets of the pieces and the total at the back, summed here in order.
std::vector<double> running_sums(const Path& path) {
  std::vector<double> offsets{0.0};
  for (const PathPiece& p : path.pieces()) offsets.push_back(offsets.back() + length(p.segment));
  return offsets;
}

// The piece whose interior holds s, by a walk from the start (s inside the path, not at a
// junction).
std::size_t piece_holding(const Path& path, double s) {
  const std::vector<double> offsets = running_sums(path);
  std::size_t k = 0;
  while (k + 1 < path.pieces().size() && !(offsets[k] < s && s < offsets[k + 1])) ++k;
  return k;
}

// Arc lengths worth probing on a path: the ends, every junction and a few random interior points.
std::vector<double> probes(std::mt19937_64& rng, const Path& path) {
  std::vector<double> s = running_sums(path);
  for (int i = 0; i < 8; ++i) s.push_back(test::uniform(rng, 0, path.length()));
  return s;
}

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

TEST(Path, LengthAndOffsetsAreTheRunningSumsOfPieceLengths) {
  const Path empty;
  EXPECT_EQ(empty.length(), 0.0);
  EXPECT_EQ(empty.offset(0), 0.0);
  EXPECT_TRUE(empty.pieces().empty());
  const std::uint64_t seed = 1;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    const std::vector<double> sums = running_sums(path);
    ASSERT_EQ(sums.size(), path.pieces().size() + 1) << where(seed, i);
    for (std::size_t k = 0; k < sums.size(); ++k) EXPECT_EQ(path.offset(k), sums[k]) << where(seed, i) << " k=" << k;
    EXPECT_EQ(path.length(), sums.back()) << where(seed, i);
    // appended in order, each piece as given
    for (std::size_t k = 0; k < path.pieces().size(); ++k) {
      EXPECT_EQ(path.pieces()[k].move, static_cast<int>(k)) << where(seed, i);
    }
  }
}

TEST(Path, LocateFindsThePieceHoldingAnInteriorPoint) {
  const std::uint64_t seed = 2;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    for (int j = 0; j < 20; ++j) {
      const double s = test::uniform(rng, 0, path.length());
      const std::size_t k = piece_holding(path, s);
      const Path::Location at = path.locate(s);
      EXPECT_EQ(at.piece, k) << where(seed, i) << " s=" << s;
      EXPECT_EQ(at.s, s - path.offset(k)) << where(seed, i) << " s=" << s;
    }
  }
}

TEST(Path, LocateAtAJunctionIsTheStartOfTheOutgoingPiece) {
  const std::uint64_t seed = 3;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    for (std::size_t k = 0; k < path.pieces().size(); ++k) {
      const double s = path.offset(k);
      if (length(path.pieces()[k].segment) == 0 || s == path.length()) continue;
      const Path::Location at = path.locate(s);
      EXPECT_EQ(at.piece, k) << where(seed, i) << " junction " << k;
      EXPECT_EQ(at.s, 0.0) << where(seed, i) << " junction " << k;
    }
  }
}

TEST(Path, LocateAtTheEndsIsTheFirstAndLastRealPieceAndClampsBeyond) {
  const std::uint64_t seed = 4;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    std::size_t first = 0;
    while (length(path.pieces()[first].segment) == 0) ++first;
    std::size_t last = path.pieces().size() - 1;
    while (length(path.pieces()[last].segment) == 0) --last;
    const double len = path.length();
    for (const double s : {0.0, -1e-9, -test::log_uniform(rng, 1e-12, 10)}) {
      const Path::Location at = path.locate(s);
      EXPECT_EQ(at.piece, first) << where(seed, i) << " s=" << s;
      EXPECT_EQ(at.s, 0.0) << where(seed, i) << " s=" << s;
      EXPECT_EQ(path.point(s), start_point(path.pieces()[first].segment)) << where(seed, i) << " s=" << s;
    }
    for (const double s : {len, len + 1e-9, len + test::log_uniform(rng, 1e-12, 10)}) {
      const Path::Location at = path.locate(s);
      EXPECT_EQ(at.piece, last) << where(seed, i) << " s=" << s;
      // the length less the offset: the piece's length up to rounding of the sums
      EXPECT_NEAR(at.s, length(path.pieces()[last].segment), kSumRounding * len) << where(seed, i) << " s=" << s;
      EXPECT_LE((path.point(s) - end_point(path.pieces()[last].segment)).norm(), 1e-12 * len) << where(seed, i);
    }
  }
}

TEST(Path, LocateNeverAnswersAZeroLengthPieceOfAPathWithLength) {
  const std::uint64_t seed = 5;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    for (const double s : probes(rng, path)) {
      const Path::Location at = path.locate(s);
      EXPECT_GT(length(path.pieces()[at.piece].segment), 0.0) << where(seed, i) << " s=" << s;
      EXPECT_GE(at.s, 0.0) << where(seed, i);
      EXPECT_LE(at.s, length(path.pieces()[at.piece].segment) + kSumRounding * path.length()) << where(seed, i);
    }
  }
}

TEST(Path, OfZeroLengthPiecesOnlyStaysAtItsPoint) {
  Path path;
  const Vec3 p(0.1, 0.2, 0.3);
  path.append(piece_of(Line{p, p}, 0));
  path.append(piece_of(Clothoid{p, Vec3(1, 0, 0), Vec3(0, 1, 0), 1.0, 1.0, 0.0}, 1));
  EXPECT_EQ(path.length(), 0.0);
  for (const double s : {-1.0, 0.0, 1.0}) {
    const Path::Location at = path.locate(s);
    EXPECT_LT(at.piece, path.pieces().size()) << s;
    EXPECT_EQ(at.s, 0.0) << s;
    EXPECT_EQ(path.point(s), p) << s;
    EXPECT_TRUE(path.tangent(s).allFinite() && path.curvature_vector(s).allFinite()) << s;
  }
}

TEST(Path, EndTangentPastTrailingZeroLengthPiecesIsTheLastRealPieces) {
  // a 1 m line along x, a quarter arc of radius 1 turning to +y, then a zero-length line (no
  // tangent) and a zero-length clothoid (tangent along x): the end is (2, 1, 0), heading +y,
  // curving towards -x
  Path path;
  path.append(piece_of(Line{Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0));
  path.append(piece_of(Arc{Vec3(1, 1, 0), Vec3(0, -1, 0), Vec3(1, 0, 0), 1.0, kPi / 2, 0.0}, 1));
  const double len = 1 + kPi / 2;
  for (const Segment& trailing : {Segment(Line{Vec3(2, 1, 0), Vec3(2, 1, 0)}),
                                  Segment(Clothoid{Vec3(2, 1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1.0, 0.0, 0.0})}) {
    path.append(piece_of(trailing, static_cast<int>(path.pieces().size())));
    EXPECT_NEAR(path.length(), len, 1e-15);
    EXPECT_EQ(path.locate(len).piece, 1U);
    EXPECT_TRUE(path.point(len).isApprox(Vec3(2, 1, 0), 1e-15));
    EXPECT_TRUE(path.tangent(len).isApprox(Vec3(0, 1, 0), 1e-15)) << path.tangent(len).transpose();
    EXPECT_TRUE(path.curvature_vector(len).isApprox(Vec3(-1, 0, 0), 1e-15)) << path.curvature_vector(len).transpose();
  }
  // and on random paths: the end tangent and curvature are the last real piece's
  const std::uint64_t seed = 6;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path random = random_path(rng);
    std::size_t last = random.pieces().size() - 1;
    while (length(random.pieces()[last].segment) == 0) --last;
    const Segment& seg = random.pieces()[last].segment;
    // the local s may fall short of the piece's end by rounding (kSumRounding)
    const Vec3 kappa = curvature_vector(seg, length(seg));
    EXPECT_LE((random.tangent(random.length()) - tangent(seg, length(seg))).norm(), 1e-12) << where(seed, i);
    EXPECT_LE((random.curvature_vector(random.length()) - kappa).norm(), 1e-9 * (1 + kappa.norm())) << where(seed, i);
  }
}

TEST(Path, PointTangentAndCurvatureAreThoseOfThePieceUnderS) {
  const std::uint64_t seed = 7;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    const std::vector<double> offsets = running_sums(path);
    for (int j = 0; j < 20; ++j) {
      const double s = test::uniform(rng, 0, path.length());
      const std::size_t k = piece_holding(path, s);
      const Segment& seg = path.pieces()[k].segment;
      const double local = s - offsets[k];
      EXPECT_EQ(path.point(s), point(seg, local)) << where(seed, i) << " s=" << s;
      EXPECT_EQ(path.tangent(s), tangent(seg, local)) << where(seed, i) << " s=" << s;
      EXPECT_EQ(path.curvature_vector(s), curvature_vector(seg, local)) << where(seed, i) << " s=" << s;
    }
    // at a junction the position is both neighbours' (the pieces are chained)
    for (std::size_t k = 1; k < path.pieces().size(); ++k) {
      const double tol = 1e-12 * std::max(1.0, path.length());
      EXPECT_LE((path.point(path.offset(k)) - start_point(path.pieces()[k].segment)).norm(), tol) << where(seed, i);
      EXPECT_LE((path.point(path.offset(k)) - end_point(path.pieces()[k - 1].segment)).norm(), tol) << where(seed, i);
    }
  }
}

TEST(Path, ForPiecesAtReportsEveryPieceTouchingS) {
  // touching: starting no later than s + tol and ending no earlier than s - tol, tol = 1e-12
  // max(1, length); in order, each with s - offset clamped onto the piece. At a junction both
  // neighbours (and any zero-length pieces between); inside a piece that piece alone.
  const std::uint64_t seed = 8;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Path path = random_path(rng);
    const std::vector<double> offsets = running_sums(path);
    const double tol = 1e-12 * std::max(1.0, path.length());
    std::vector<double> at = probes(rng, path);
    for (std::size_t k = 0; k < offsets.size(); ++k) {
      for (const double d : {-2.0, -0.5, 0.5, 2.0}) at.push_back(offsets[k] + d * tol);
    }
    for (const double s : at) {
      std::vector<std::pair<std::size_t, double>> expected;
      for (std::size_t k = 0; k < path.pieces().size(); ++k) {
        if (offsets[k] - tol <= s && s <= offsets[k + 1] + tol) {
          expected.emplace_back(k, std::clamp(s - offsets[k], 0.0, length(path.pieces()[k].segment)));
        }
      }
      std::vector<std::pair<std::size_t, double>> got;
      path.for_pieces_at(s, [&](std::size_t k, double local) { got.emplace_back(k, local); });
      EXPECT_EQ(got, expected) << where(seed, i) << " s=" << s;
      const bool junction = std::any_of(offsets.begin() + 1, offsets.end() - 1,
                                        [&](double o) { return std::abs(s - o) <= tol; });
      if (!junction && s > tol && s < path.length() - tol) {
        EXPECT_EQ(got.size(), 1U) << where(seed, i) << " s=" << s << " is inside one piece";
      }
    }
    // every interior junction reports the pieces on both sides of it
    for (std::size_t k = 1; k < path.pieces().size(); ++k) {
      std::vector<std::size_t> got;
      path.for_pieces_at(offsets[k], [&](std::size_t j, double) { got.push_back(j); });
      EXPECT_NE(std::find(got.begin(), got.end(), k - 1), got.end()) << where(seed, i) << " junction " << k;
      EXPECT_NE(std::find(got.begin(), got.end(), k), got.end()) << where(seed, i) << " junction " << k;
    }
  }
}

}  // namespace
}  // namespace blendbench
