#pragma once
/**
 * @file
 * A scenario: what a scene runs for its model path, bodies and tools (the accurate
 * tissue alone, the accurate suture alone, the accurate needle pass and stitch, the
 * realtime world, ...). Scenarios register themselves like models (core/registry.h):
 * each says which scenes it runs (applies()), may declare its own subsections, and is
 * built from the parsed scene, checking what only it needs; a new scenario is one new
 * file under source/scene/scenarios/.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/io/recorder.h>
#include <suturesim/scene/scene_parameters.h>

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace suturesim::scene
{
  class Scenario
  {
  public:
    virtual ~Scenario() = default;

    /// Runs the scene into @p recorder (whose summary it fills). InputError for input
    /// found bad only now (the mesh, boundary names, probes), SolverError for a solve
    /// that failed after every cut-back (the last accepted state kept).
    virtual void
    run(io::Recorder &recorder) = 0;

    /// Whether the scenario writes checkpoints and goes on from one (io/checkpoint.h,
    /// Time/Checkpoint steps, suturesim --restart); the others refuse both.
    virtual bool
    writes_checkpoints() const
    {
      return false;
    }

    struct Entry
    {
      std::string name;
      /// What it runs, for --help.
      std::string description;
      /// Declares the scenario's own subsections (may be empty).
      std::function<void(dealii::ParameterHandler &)> declare_parameters;
      /// Whether it runs the scene (name, model path, bodies, needle, closure parsed).
      std::function<bool(const SceneParameters &)> applies;
      /// Parses the rest of what it needs from @p prm into @p scene and checks it
      /// (InputError naming file, line and key); kept by the caller for the run.
      std::function<std::unique_ptr<Scenario>(dealii::ParameterHandler &prm, SceneParameters &scene)> create;
    };

    class Registry
    {
    public:
      static Registry &
      instance();
      /// Returns true so that a namespace-scope `const bool` can call it at load time.
      bool
      add(Entry entry);
      /// The scenario that runs @p scene, nullptr if none does.
      const Entry *
      find(const SceneParameters &scene) const;
      const std::vector<Entry> &
      all() const
      {
        return entries;
      }

    private:
      Registry() = default;
      std::vector<Entry> entries;
    };
  };
} // namespace suturesim::scene
