#pragma once
/**
 * @file
 * The record of an accurate suture (Cosserat rod) run (rod::StateObserver): per accepted
 * state a forces.csv row (force and moment at both supports, the tip, the largest
 * axial force, the elastic energy, the nodes in self-contact), the metrics
 * tip_position, max_axial_force, final_max_axial_force, elastic_energy,
 * start_reaction, last_reaction, contact_nodes, and suture_*.vtu when due.
 */

#include <suturesim/core/time_parameters.h>
#include <suturesim/io/polyline_writer.h>
#include <suturesim/io/recorder.h>
#include <suturesim/rod/rod_integrator.h>

#include <deal.II/base/conditional_ostream.h>

#include <chrono>
#include <string>

namespace suturesim::scene
{
  struct SceneParameters;

  /// The rod as a polyline for suture_*.vtu: nodes with radius and contact force, per
  /// segment the axial and shear force, bending and twisting moment, twist, curvature.
  io::PolylineData
  polyline_data(const rod::RodModel &model, double radius);

  /// Writes suture_<index>.vtu of @p model into the recorder's folder (rank 0) and
  /// adds it to suture.pvd.
  void
  write_suture_vtu(const rod::RodModel &model, double radius, unsigned index, double t, io::Recorder &recorder);

  class SutureRecorder : public rod::StateObserver
  {
  public:
    /// Sets the forces.csv columns.
    SutureRecorder(rod::RodProblem &problem, io::Recorder &recorder);

    void
    accepted(double t, const nlohmann::json &statistics, const Eigen::VectorXd *residual) override;

    std::string
    keep(double t) override;

  private:
    rod::RodProblem &problem;
    io::Recorder          &recorder;
    double                 last_output  = -1;
    unsigned               output_index = 0;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  };

  /// The opening every scenario of the rod alone shares: the rod built from the scene,
  /// summary.json's scene and rod entries (RunSummary::begin, rod), the banner line
  /// "suturesim: scene '<name>', suture of <n> Cosserat rod elements<what>" and the record.
  struct SutureRun
  {
    SutureRun(const SceneParameters &scene, io::Recorder &recorder, dealii::ConditionalOStream &banner,
              const std::string &what);

    rod::RodProblem problem;
    SutureRecorder  observer;
  };
} // namespace suturesim::scene
