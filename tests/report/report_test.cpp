#include "blendbench/report/report.hpp"

#include <gtest/gtest.h>

#include "support/csv.hpp"
#include "blendbench/corner/blend.hpp"

namespace blendbench {
namespace {

Program square() {
  Program program;
  const Vec3 p[] = {{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}};
  for (int i = 0; i < 2; ++i) {
    Move& m = program.moves.emplace_back();
    m.geometry = Line{p[i], p[i + 1]};
    m.limits = {0.1, 1, 1, 10};
  }
  return program;
}

TEST(Report, PathCsvIsUniformInSWithEveryJunctionOnce) {
  const Path path = blend(square());
  const std::string csv = path_csv(path, 0.00005);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "s,x,y,z,tx,ty,tz,kappa");
  const auto r = test::parse_csv(csv).rows;
  // 200 mm at 0.05 mm: 4001 samples
  ASSERT_EQ(r.size(), 4001u);
  for (std::size_t i = 1; i < r.size(); ++i) {
    EXPECT_NEAR(r[i][0] - r[i - 1][0], 0.05, 1e-9) << i;
    EXPECT_EQ(r[i].size(), 8u);
  }
  EXPECT_NEAR(r.back()[0], 200.0, 1e-9);
  EXPECT_NEAR(r.back()[2], 100.0, 1e-9);  // y of the end point in mm
}

TEST(Report, CornersJsonUsesContractUnits) {
  const Path path = blend(square());
  const nlohmann::json j = corners_json(path);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["method"], "none");
  EXPECT_EQ(j[0]["case"], "exact_stop");
  EXPECT_TRUE(j[0]["feed_max_mm_per_min"].is_number());
  for (const char* key : {"index", "method", "case", "length_mm", "deviation_mm", "kappa_max_per_mm",
                          "sharpness_max_per_mm2", "feed_max_mm_per_min"}) {
    EXPECT_TRUE(j[0].contains(key)) << key;
  }
}

TEST(Report, CornerNamesAreTheIndexAndTheProgramLine) {
  EXPECT_EQ(corner_name(7, SourceRef{"/parts/bracket.ngc", 110, 5}), "C7 (bracket.ngc:110)");
  EXPECT_EQ(corner_name(0, SourceRef{"", 12, 0}), "C0 (line 12)");
  EXPECT_EQ(corner_name(3, SourceRef{}), "C3");
  // the blender's corners carry the move's source: the name follows it
  Program program = square();
  program.moves[0].where = {"a/b/part.yaml", 21, 7};
  program.moves[0].transition = {Method::kArc, 0.01};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 1U);
  EXPECT_EQ(corner_name(path.corners[0].index, path.corners[0].source), "C0 (part.yaml:21)");
}

}  // namespace
}  // namespace blendbench
