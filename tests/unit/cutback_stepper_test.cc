// The step-size control of the implicit solvers (core/cutback_stepper.h): fixed steps
// with halvings of a failing step, and adaptive steps that grow and shrink with the
// Newton iterations a step took and end on the caller's events.
#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

using suturesim::StepAttempt;
using suturesim::StepControl;
using suturesim::StepHooks;

namespace
{
  struct Steps
  {
    std::vector<double> t, dt;
  };

  /// Runs @p control with attempts that converge in iterations(t_new) Newton iterations
  /// (or fail where failing(t_new, dt)), an event list @p events; the accepted steps.
  Steps
  run(const StepControl &control, const std::function<unsigned(double)> &iterations,
      const std::vector<double> &events = {}, const std::function<bool(double, double)> &failing = {})
  {
    Steps     steps;
    StepHooks hooks;
    hooks.attempt = [&](const double tn, const double dt) {
      if (failing && failing(tn, dt))
        return StepAttempt{StepAttempt::Outcome::failed, "test", 0};
      return StepAttempt{StepAttempt::Outcome::converged, "", iterations(tn)};
    };
    hooks.undo   = [](const StepAttempt &, double, double) {};
    hooks.accept = [&](const double tn, const double dt, unsigned) {
      steps.t.push_back(tn);
      steps.dt.push_back(dt);
    };
    hooks.fail       = [](double, unsigned, const std::string &) {};
    hooks.next_event = [&](const double t) {
      for (const double e : events)
        if (e > t + 1e-12)
          return e;
      return std::numeric_limits<double>::infinity();
    };
    suturesim::run_with_cutbacks(control, hooks);
    return steps;
  }
} // namespace

TEST(CutbackStepper, FixedStepsKeepTheirGridAndIgnoreEvents)
{
  // Max step size 0: the nominal grid, whatever the iterations and the events
  const Steps s = run({1, 0.1, 6, 0}, [](double) { return 1u; }, {0.25, 0.55});
  ASSERT_EQ(s.t.size(), 10u);
  for (std::size_t k = 0; k < s.t.size(); ++k)
    {
      EXPECT_NEAR(s.t[k], 0.1 * (k + 1), 1e-12);
      EXPECT_EQ(s.dt[k], 0.1);
    }
}

TEST(CutbackStepper, AdaptiveStepsGrowWhenEasyShrinkWhenHardAndStayInTheirBounds)
{
  // target 4: one iteration doubles the step (√4 = 2), up to Max step size 0.4
  const Steps easy = run({2, 0.1, 6, 0, 0.4, 4}, [](double) { return 1u; });
  const std::vector<double> expected{0.1, 0.2, 0.4, 0.4, 0.4, 0.4, 0.1};
  ASSERT_EQ(easy.dt.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(easy.dt[k], expected[k], 1e-12) << k; // the last one ends on the end time
  // nine iterations: the step times √(4/9) = 2/3 each time, down to 0.1/2⁶
  const Steps hard = run({0.31, 0.1, 6, 0, 0.4, 4}, [](double) { return 9u; });
  ASSERT_GT(hard.dt.size(), 12u);
  for (std::size_t k = 1; k + 1 < hard.dt.size(); ++k) // the last one ends on the end time
    EXPECT_NEAR(hard.dt[k], std::max(hard.dt[k - 1] * 2.0 / 3.0, std::ldexp(0.1, -6)), 1e-12) << k;
  EXPECT_NEAR(hard.dt.rbegin()[1], std::ldexp(0.1, -6), 1e-12);
  // four iterations, the target: the step stays
  const Steps steady = run({0.5, 0.1, 6, 0, 0.4, 4}, [](double) { return 4u; });
  EXPECT_EQ(steady.dt.size(), 5u);
}

TEST(CutbackStepper, AdaptiveStepsEndOnEventsAndStartAgainFromTheNominalStep)
{
  const Steps s = run({1, 0.1, 6, 0, 0.8, 4}, [](double) { return 1u; }, {0.35});
  // 0.1, 0.2 (to 0.3), the 0.4 that follows cut to 0.05 to end on the event, then from
  // the nominal step again: 0.1, 0.2, and the 0.4 cut to 0.35 to end on the end time
  const std::vector<double> t{0.1, 0.3, 0.35, 0.45, 0.65, 1.0};
  ASSERT_EQ(s.t.size(), t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    EXPECT_NEAR(s.t[k], t[k], 1e-12) << k;
  EXPECT_EQ(s.t[2], 0.35); // exactly on the event
}

TEST(CutbackStepper, AfterAFailedStepTheStepReturnsToTheNominalBeforeItGrowsAgain)
{
  // steps 0.1, 0.2 grown to 0.4: that one fails once and is halved; the step after it
  // is the nominal 0.1 (a hard place: no growth straight back), then it grows again
  bool       failed  = false;
  const auto failing = [&](double, const double dt) { return dt > 0.3 && !failed && (failed = true); };
  const Steps s      = run({2, 0.1, 6, 0, 0.4, 4}, [](double) { return 1u; }, {}, failing);
  const std::vector<double> expected{0.1, 0.2, 0.2, 0.1, 0.2, 0.4};
  ASSERT_GE(s.dt.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(s.dt[k], expected[k], 1e-12) << k;
  EXPECT_TRUE(failed);
}

// Collapsed steps (the header's guard): steps that only converge far below the nominal
// one are stopped once the steps taken plus those to go at the last 200's pace exceed
// Maximum steps, with the state kept, after a bounded number of steps.
TEST(CutbackStepper, CollapsedStepsStopTheRunWithinABoundedNumberOfSteps)
{
  StepHooks   hooks;
  std::size_t accepted = 0;
  double      kept     = -1;
  hooks.attempt        = [](double, const double dt) {
    // converges only below 1e-6 of the nominal 0.01 s: the floor 0.01/2^20 passes
    return dt < 1e-8 ? StepAttempt{} : StepAttempt{StepAttempt::Outcome::failed, "too long", 0};
  };
  hooks.undo   = [](const StepAttempt &, double, double) {};
  hooks.accept = [&](double, double, unsigned) { ++accepted; };
  hooks.fail   = [](double, unsigned, const std::string &) {};
  hooks.keep   = [&](const double t) {
    kept = t;
    return std::string("here.pvd");
  };
  try
    {
      suturesim::run_with_cutbacks({1, 0.01, 20, 0, 0, 4, 1e6}, hooks);
      FAIL() << "a run of 1e8 steps at the floor went on";
    }
  catch (const suturesim::SolverError &e)
    {
      const std::string what = e.what();
      EXPECT_NE(what.find("steps collapsed"), std::string::npos) << what;
      EXPECT_NE(what.find("Time/Maximum steps = 1e+06"), std::string::npos) << what;
      EXPECT_NE(what.find("here.pvd"), std::string::npos) << what;
    }
  EXPECT_EQ(accepted, 200u); // the first full window already shows the pace
  EXPECT_GT(kept, 0);
}

// The same guard leaves alone a run whose steps shrink through an event and recover: at
// t = 0.5 every step longer than 0.01/2^6 fails, once; 1 000 nominal steps under a budget
// of 2 000 (the pace right after the event projects 1 035).
TEST(CutbackStepper, ABurstOfShortStepsThroughAnEventIsNotACollapse)
{
  bool        hit = false;
  const Steps s   = run({10, 0.01, 6, 0, 0, 4, 2000}, [](double) { return 2u; }, {},
                      [&](const double tn, const double dt) {
                        const bool fails = !hit && tn > 0.5 && dt > std::ldexp(0.01, -6) * 1.5;
                        hit              = hit || (tn > 0.5 && !fails);
                        return fails;
                      });
  EXPECT_GT(s.t.size(), 1000u);
  EXPECT_NEAR(s.t.back(), 10, 1e-9);
  EXPECT_LE(s.dt.size(), 1020u); // 1 000 nominal steps and a dozen through the event
}
