// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of core: vectors, domain minimum image, registry dispatch, stop requests.
#include <gtest/gtest.h>

#include <csignal>

#include "core/domain.hpp"
#include "core/error.hpp"
#include "core/registry.hpp"
#include "core/stop.hpp"
#include "core/vec3.hpp"

using namespace gf;

TEST(Vec3, CrossAndDot) {
  const Vec3 a{1, 0, 0}, b{0, 1, 0};
  EXPECT_EQ(cross(a, b), (Vec3{0, 0, 1}));
  EXPECT_DOUBLE_EQ(dot(a + b, a + b), 2.0);
}

// A failed REQUIRE names its check and its source file relative to the project, not the path
// of the machine the program was built on.
TEST(Require, NamesTheCheckAndTheSourceFileInTheProject) {
  const int n = 3;
  try {
    REQUIRE(n < 2, "n is {}", n);
    FAIL() << "REQUIRE did not throw";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("n is 3 (check 'n < 2' failed at tests/unit/test_core.cpp:", 0), 0u) << m;
  }
}

TEST(Domain, MinimumImageAndWrap) {
  Domain d{{0, 0, 0}, {1, 2, 3}, {true, false, true}};
  const Vec3 r = d.delta({0.95, 0.5, 0.1}, {0.05, 0.5, 2.9});
  EXPECT_NEAR(r.x, -0.1, 1e-14);
  EXPECT_NEAR(r.z, 0.2, 1e-14);
  Vec3 p{1.25, 3.0, -0.5};
  d.wrap(p);
  EXPECT_NEAR(p.x, 0.25, 1e-14);
  EXPECT_EQ(p.y, 3.0);  // not periodic: untouched
  EXPECT_NEAR(p.z, 2.5, 1e-14);
}

struct KA {
  static constexpr std::string_view key = "a";
  static int value() { return 1; }
};
struct KB {
  static constexpr std::string_view key = "b";
  static int value() { return 2; }
};

TEST(Registry, LookupAndDispatch) {
  using L = TypeList<KA, KB>;
  EXPECT_EQ(index_of_key(L{}, "b"), 1);
  EXPECT_EQ(index_of_key(L{}, "c"), -1);
  EXPECT_EQ(dispatch_index(L{}, 1, []<class T>() { return T::value(); }), 2);
}

TEST(Stop, FirstSignalIsRecordedSecondEndsTheProcess) {
  stop::install_handlers();
  EXPECT_EQ(stop::requested(), 0);
  std::raise(SIGINT);  // recorded, the process goes on
  EXPECT_EQ(stop::requested(), SIGINT);
  EXPECT_STREQ(stop::signal_name(stop::requested()), "SIGINT");
  EXPECT_EQ(stop::exit_status(SIGTERM), 143);
  // A second signal of either kind ends the process as the default action would.
  EXPECT_EXIT(std::raise(SIGTERM), ::testing::KilledBySignal(SIGTERM), "");
  stop::reset();
  EXPECT_EQ(stop::requested(), 0);
  stop::install_handlers();
  std::raise(SIGTERM);
  EXPECT_EQ(stop::requested(), SIGTERM);
  stop::reset();
}

TEST(Stop, TimeLimitAsksToStopOnceItHasPassed) {
  stop::set_time_limit(3600.0);
  EXPECT_EQ(stop::requested(), 0);
  stop::set_time_limit(1e-9);
  EXPECT_EQ(stop::requested(), stop::kTimeLimit);
  EXPECT_STREQ(stop::signal_name(stop::kTimeLimit), "time limit");
  EXPECT_EQ(stop::exit_status(stop::kTimeLimit), 3);
  stop::reset();
  EXPECT_EQ(stop::requested(), 0);
}
