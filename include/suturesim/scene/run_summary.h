#pragma once
/**
 * @file
 * The layout of summary.json, in one place: every scenario describes its run through
 * these functions, so the keys a reader (postprocess/, the study layer, the tests)
 * relies on are written here and nowhere else. The parts a component owns (the
 * metrics of the closure, of the needle, of a recorder) are written by that component
 * into "metrics"; io::Recorder adds version, commit, MPI processes, status, and
 * main() the wall time.
 *
 *   scene, scene_file, model, bodies        the scene (begin())
 *   mesh                                    the tissue's mesh and discretisation, with
 *                                           its representative size h = (V/N)^(1/3)
 *                                           (V its volume, N its cells: Celik et al.
 *                                           2008, eq. 1), what a convergence study's
 *                                           order and GCI are computed against
 *   suture                                  the suture's discretisation and section
 *   realtime                                the realtime models and haptic loop
 *   metrics                                 the run's measurements (SI units)
 *   steps                                   per accepted step: the solver's account
 *   incomplete                              why a run that ended did not do what its
 *                                           scene asked (absent: it did)
 *   solver, timings                         totals, wall time per section
 */

#include <suturesim/scene/scene_parameters.h>

#include <deal.II/base/timer.h>

#include <nlohmann/json.hpp>

#include <string>

namespace suturesim::scene
{
  class RunSummary
  {
  public:
    explicit RunSummary(nlohmann::json &summary)
      : json(summary)
    {}

    /// scene, scene_file, model, bodies; empty metrics and steps.
    void
    begin(const SceneParameters &scene);

    /// The accurate tissue's mesh: description, cells, DoFs, element degree and
    /// formulation, its representative size from @p volume (m^3);
    /// @p surface_triangles when the boundary was triangulated (> 0).
    void
    fe_mesh(const std::string &description, std::uint64_t cells, std::uint64_t dofs, double volume,
            const tissue::TissueParameters &tissue, std::size_t surface_triangles = 0);

    /// The realtime tissue's mesh: tetrahedra from gmsh and their boundary, its
    /// representative size from @p volume (m^3).
    void
    simplex_mesh(const std::string &description, std::size_t vertices, std::size_t tetrahedra, double volume,
                 std::size_t surface_triangles);

    /// The accurate suture alone: elements, centreline, section stiffnesses.
    void
    rod(const rod::RodParameters &parameters, std::size_t elements);

    /// The accurate suture coupled to the tissue by a needle's pierce points.
    void
    coupled_suture(std::size_t elements, double length, double coupling_tolerance);

    /// The realtime suture: nodes, radius, EA, EI.
    void
    realtime_suture(std::size_t nodes, double radius, double EA, double EI);

    /// The needle: its punctures and passages as "events" (in time order), the first
    /// entry and exit puncture forces and @p peak_pull_force under "metrics", the needle
    /// and its pass under "needle"; the realtime @p pierce_model when given.
    void
    needle(const NeedleParameters &needle, const std::vector<coupling::PunctureEvent> &events, double peak_pull_force,
           const std::string &pierce_model = "");

    /// Seed 003's evaluation of the needle's stitches through @p wound
    /// (tearing/stitch_evaluation.h) under "metrics.stitch_evaluation"; returns them for
    /// the same table as stitches.csv (tearing::stitches_csv()).
    std::vector<tearing::StitchEvaluation>
    stitch_evaluation(const NeedleParameters &needle, const std::vector<coupling::PunctureEvent> &events,
                      const tearing::Wound &wound, const tearing::StitchLimits &limits);

    /// A pass that reached @p t without what it is for is incomplete (incomplete()): its
    /// tip turned past the planned exit without a puncture, or, with a @p suture on the
    /// needle, the suture's far end was drawn out of the tissue (too short for the pass;
    /// without one, the needle leaving its holes is the end of the pass).
    void
    pass_outcome(const NeedleParameters &needle, const std::vector<coupling::PunctureEvent> &events, double t,
                 bool suture);

    /// Marks the run incomplete: it ran to its end, but did not do what the scene asked,
    /// for @p reason ("incomplete": the reasons; main() then finishes with status
    /// "incomplete" and exit code 6).
    void
    incomplete(const std::string &reason);

    /// One accepted step's solver account at time @p t.
    void
    step(const nlohmann::json &statistics, double t);

    /// The solver's totals (merged into "solver").
    void
    solver(const nlohmann::json &totals);

    /// The direct method's factorisation memory, estimated before it (the resource
    /// guard's) and as made: "solver"'s factorization_memory_estimate and
    /// factorization_memory, B; and its counts: factorizations, reused_solves,
    /// reuse_iterations, reuse_failures (LinearSolver::Statistics).
    void
    factorization(const tissue::LinearSolver::Statistics &linear);

    /// Wall time per section of @p timer, s.
    void
    timings(const dealii::TimerOutput &timer);

    nlohmann::json &
    metrics()
    {
      return json["metrics"];
    }
    /// The realtime block (models, rate, substeps, stability).
    nlohmann::json &
    realtime()
    {
      return json["realtime"];
    }
    nlohmann::json &
    whole()
    {
      return json;
    }

  private:
    nlohmann::json &json;
  };
} // namespace suturesim::scene
