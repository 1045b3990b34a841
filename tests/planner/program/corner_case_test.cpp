// Tests of the corner-case and fallback names (planner/program/src/corner_case.cpp): every
// value has one name that reads back, and the README's table of special cases names only
// values the code has, and every one of them.

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "blendbench/program/corner_case.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

// The values of an enum, found as the integers that to_string names (it answers "unknown"
// beyond the last), so a value added later is covered without touching this file.
template <typename Enum>
int value_count() {
  int n = 0;
  while (n < 64 && to_string(static_cast<Enum>(n)) != "unknown") ++n;
  return n;
}
const int kCases = value_count<CornerCase>();
const int kFallbacks = value_count<Fallback>();

TEST(CornerCase, EveryValueHasAUniqueNameThatReadsBack) {
  EXPECT_GT(kCases, static_cast<int>(CornerCase::kNonPlanar));
  EXPECT_GT(kFallbacks, static_cast<int>(Fallback::kBiclothoidBezier));
  std::set<std::string> names;
  for (int i = 0; i < kCases; ++i) {
    const auto c = static_cast<CornerCase>(i);
    const std::string name(to_string(c));
    EXPECT_NE(name, "unknown") << i;
    EXPECT_TRUE(names.insert(name).second) << "duplicate name " << name;
    EXPECT_EQ(corner_case_from_string(name), c) << name;
  }
  EXPECT_FALSE(corner_case_from_string("Regular").has_value());
  EXPECT_FALSE(corner_case_from_string("").has_value());
  std::set<std::string> fallbacks;
  for (int i = 0; i < kFallbacks; ++i) {
    EXPECT_TRUE(fallbacks.insert(std::string(to_string(static_cast<Fallback>(i)))).second) << i;
  }
  EXPECT_EQ(to_string(Fallback::kNone), "");
}

// The methods table of docs/methods.md ("special cases reported") against the enums.
TEST(CornerCase, MethodsTableNamesExactlyTheCasesTheCodeReports) {
  std::ifstream in(test::source_path("docs/methods.md"));
  ASSERT_TRUE(in) << "docs/methods.md";
  std::stringstream text;
  text << in.rdbuf();
  std::set<std::string> documented;
  std::string line;
  bool in_table = false;
  while (std::getline(text, line)) {
    if (line.find("special cases reported (`case`)") != std::string::npos) {
      in_table = true;
      continue;
    }
    if (in_table && line.rfind("|", 0) != 0) break;
    if (!in_table || line.rfind("|---", 0) == 0) continue;
    // the fourth column: cases and fallbacks in backticks
    std::vector<std::string> cells;
    std::stringstream row(line);
    std::string cell;
    while (std::getline(row, cell, '|')) cells.push_back(cell);
    ASSERT_GE(cells.size(), 5u) << line;
    const std::regex quoted("`([^`]+)`");
    for (auto it = std::sregex_iterator(cells[4].begin(), cells[4].end(), quoted); it != std::sregex_iterator(); ++it) {
      documented.insert((*it)[1]);
    }
  }
  ASSERT_FALSE(documented.empty()) << "the methods table of docs/methods.md was not found";
  std::set<std::string> known_fallbacks;
  for (int i = 1; i < kFallbacks; ++i) known_fallbacks.insert(std::string(to_string(static_cast<Fallback>(i))));
  for (const std::string& name : documented) {
    EXPECT_TRUE(corner_case_from_string(name).has_value() || known_fallbacks.count(name) > 0)
        << "the README names '" << name << "', which is neither a corner case nor a fallback";
  }
  for (int i = 1; i < kCases; ++i) {
    const std::string name(to_string(static_cast<CornerCase>(i)));
    EXPECT_TRUE(documented.count(name) > 0) << "the README's table does not name the case '" << name << "'";
  }
  for (const std::string& name : known_fallbacks) {
    EXPECT_TRUE(documented.count(name) > 0) << "the README's table does not name the fallback '" << name << "'";
  }
}

}  // namespace
}  // namespace blendbench
