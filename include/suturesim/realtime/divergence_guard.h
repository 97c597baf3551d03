#pragma once
/**
 * @file
 * The divergence guard of the realtime path: after every step it looks for a position or
 * velocity that is not finite and for runaway kinetic energy, and names the step, the
 * node and the likely cause in one line. Runaway means E_kin > ½ M (L/h)², M the total
 * mass, L the scene's size and h the step: the whole body crossing the scene in one step,
 * which no physical motion here does, while an unstable explicit integration passes it
 * within tens of steps of going unstable (its fastest mode grows by a fixed factor per
 * step).
 */

#include <suturesim/realtime/system.h>

#include <stdexcept>
#include <string>

namespace suturesim::realtime
{
  /// A run that diverged; what() is the guard's one-line diagnostic. The world is back
  /// at its last good state when this is thrown.
  class DivergenceError : public std::runtime_error
  {
  public:
    DivergenceError(const std::string &what, const std::size_t step)
      : std::runtime_error(what)
      , step(step)
    {}
    std::size_t step; ///< the step that diverged (1-based)
  };

  class DivergenceGuard
  {
  public:
    /// @p step_size h of one (haptic) step, s; @p context is appended to the likely
    /// cause (e.g. the stability limit of the integrator).
    void
    setup(const System &system, double step_size, std::string likely_cause);

    /// Empty when the state is sound, else the diagnostic.
    std::string
    check(const System &system, std::size_t step) const;

  private:
    std::string
    describe_node(const System &system, std::uint32_t node) const;

    double      energy_bound = 0;
    std::string cause;
  };
} // namespace suturesim::realtime
