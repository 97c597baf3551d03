#pragma once
/**
 * @file
 * The record of an accurate tissue run (tissue::StateObserver): per accepted state a
 * forces.csv row (reaction on every Dirichlet boundary, probe displacements), the
 * metrics of the last state (metrics.reaction_force.<boundary>, probes.<name>,
 * <name>_displacement_{x,y,z}), the solver's account into summary.json "steps", and a
 * tissue_*.vtu file when due (Time/Output interval); at the end (or the last accepted
 * state of a failed run) the surface displacement (io/surface_field.h).
 */

#include <suturesim/core/time_parameters.h>
#include <suturesim/io/recorder.h>
#include <suturesim/tissue/time_integrator.h>

#include <string>

namespace suturesim::scene
{
  class TissueRecorder : public tissue::StateObserver
  {
  public:
    /// Sets the forces.csv columns of @p model's boundaries and probes.
    TissueRecorder(tissue::TissueModel &model, const TimeParameters &time, io::Recorder &recorder);

    void
    accepted(double t, const nlohmann::json &statistics, const tissue::TissueModel::Vector *velocity,
             const tissue::TissueModel::Vector *acceleration) override;
    std::string
    keep_last_accepted() override;
    double
    last_accepted_time() const override
    {
      return last_accepted;
    }
    void
    totals(const nlohmann::json &solver) override;

  private:
    /// surface_displacement.json of the last accepted state (collective).
    void
    write_surface() const;

    tissue::TissueModel  &model;
    const TimeParameters &time;
    io::Recorder         &recorder;
    std::string           last_file;
    double                last_output   = -1;
    double                last_accepted = 0;
    bool                  any           = false;
    unsigned              output_index  = 0;
  };
} // namespace suturesim::scene
