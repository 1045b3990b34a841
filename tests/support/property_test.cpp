// The property tests' environment (support/property.hpp): the case count and the seed offset a
// developer or a scheduled job sets, and the failure text that replays a case.

#include "support/property.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace blendbench::test {
namespace {

// Sets (or unsets) one variable for a test's duration and restores what was there.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) ::setenv(name, value, 1);
    else ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(PropertyEnvironment, WithoutAnOffsetEachSeedIsItsOwnGenerator) {
  const ScopedEnv env("BLENDBENCH_PROPERTY_SEED", nullptr);
  for (const std::uint64_t seed : {0ULL, 7ULL, 1000ULL, 5025986ULL}) {
    EXPECT_EQ(make_rng(seed)(), std::mt19937_64(seed)()) << seed_text(seed);
    EXPECT_EQ(seed_text(seed), "seed=" + std::to_string(seed));
  }
  const ScopedEnv empty("BLENDBENCH_PROPERTY_SEED", "");
  EXPECT_EQ(seed_offset(), 0U);
}

TEST(PropertyEnvironment, AnOffsetMovesEverySeedAndTheFailureTextNamesIt) {
  const ScopedEnv env("BLENDBENCH_PROPERTY_SEED", "10000000");
  EXPECT_EQ(seed_offset(), 10000000U);
  for (const std::uint64_t seed : {0ULL, 7ULL, 1000ULL}) {
    std::mt19937_64 moved = make_rng(seed);
    std::mt19937_64 plain(seed + 10000000);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(moved(), plain());
    EXPECT_NE(make_rng(seed)(), std::mt19937_64(seed)());
  }
  EXPECT_EQ(seed_text(42), "seed=42 (BLENDBENCH_PROPERTY_SEED=10000000)");
}

TEST(PropertyEnvironment, AnOffsetThatIsNoWholeNumberStopsTheRun) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  for (const char* bad : {"12x", "-3", "seed", "1.5"}) {
    EXPECT_DEATH(
        {
          ::setenv("BLENDBENCH_PROPERTY_SEED", bad, 1);
          (void)make_rng(1);
        },
        "BLENDBENCH_PROPERTY_SEED=.* is not a whole number")
        << bad;
  }
}

TEST(PropertyEnvironment, TheCaseCountFollowsTheCountOrTheScale) {
  {
    const ScopedEnv cases("BLENDBENCH_PROPERTY_CASES", nullptr);
    const ScopedEnv scale("BLENDBENCH_PROPERTY_SCALE", nullptr);
    EXPECT_EQ(property_cases(300), 300);
  }
  {
    const ScopedEnv cases("BLENDBENCH_PROPERTY_CASES", nullptr);
    const ScopedEnv scale("BLENDBENCH_PROPERTY_SCALE", "0.25");
    EXPECT_EQ(property_cases(300), 75);
    EXPECT_EQ(property_cases(1), 1);  // at least one case
  }
  {
    const ScopedEnv cases("BLENDBENCH_PROPERTY_CASES", "17");
    const ScopedEnv scale("BLENDBENCH_PROPERTY_SCALE", "20");
    EXPECT_EQ(property_cases(300), 17);  // the count wins over the scale
  }
}

TEST(PropertyEnvironment, AScaleBelowOneSamplesAFixedListAndTheSeedsCoverItBetweenThem) {
  const ScopedEnv unset("BLENDBENCH_PROPERTY_SEED", nullptr);
  {
    const ScopedEnv none("BLENDBENCH_PROPERTY_SCALE", nullptr);
    for (std::size_t i = 0; i < 9; ++i) EXPECT_TRUE(property_sample(i)) << i;
  }
  const ScopedEnv quarter("BLENDBENCH_PROPERTY_SCALE", "0.25");
  std::vector<int> checked(16, 0);
  for (const char* seed : {"0", "1", "2", "3"}) {
    const ScopedEnv offset("BLENDBENCH_PROPERTY_SEED", seed);
    int taken = 0;
    for (std::size_t i = 0; i < checked.size(); ++i) {
      if (property_sample(i)) {
        ++checked[i];
        ++taken;
      }
    }
    EXPECT_EQ(taken, 4) << "BLENDBENCH_PROPERTY_SEED=" << seed;
  }
  for (std::size_t i = 0; i < checked.size(); ++i) EXPECT_EQ(checked[i], 1) << i;
  // a list whose items cost four ordinary ones: every 16th
  int costly = 0;
  for (std::size_t i = 0; i < 64; ++i) costly += property_sample(i, 4) ? 1 : 0;
  EXPECT_EQ(costly, 4);
  const ScopedEnv more("BLENDBENCH_PROPERTY_SCALE", "3");
  EXPECT_TRUE(property_sample(1));
  EXPECT_TRUE(property_sample(1, 4));
}

}  // namespace
}  // namespace blendbench::test
