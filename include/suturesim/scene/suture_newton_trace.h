#pragma once
/**
 * @file
 * Why a suture Newton solve fails (Suture/Newton/Trace failures): every iteration of
 * the accurate stitch's suture solves is split by what contributes to its residual
 * (rod::RodModel::residual_parts(): the elements, self-contact, the applied loads, the
 * pierce points' ties and friction, and each nodal term such as the stabilising drag
 * and the contact with the tissue), and when a solve fails its iterations are appended
 * to suture_newton_trace.csv. Per iteration: the free residual's norm per part, the
 * step taken (fraction of the Newton correction, its largest node move and turn), and
 * at the node with the largest residual each part's share. A solve that cycles shows
 * which parts trade the residual between them; one that crawls shows the step cap at
 * work. Beside it, suture_newton_trace_points.csv has each pierce point on the thread
 * per iteration: its carrier element, where its projection lies on it (u beyond [0, 1]:
 * past a node), its slip ζ − ζ_a, stick or slip, normal and friction force, and its
 * distance across the thread: what a tie that switches between iterates does.
 */

#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/rod/rod_model.h>

#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::scene
{
  /// A trace's points file: @p file with "_points" before its extension.
  std::string
  trace_points_file(const std::string &file);
  /// The columns of a pierce point's state in a trace's points file, after the row's own.
  inline constexpr const char *point_state_columns =
    "point,element,u [1],slip [m],slipping [0|1],normal [N],friction [N],across [m]";
  /// One point's state in those columns, each preceded by a comma.
  void
  write_point_state(std::ostream &out, const coupling::TissueNeedle::ThreadPointState &p);
  /// Appends to a trace's CSV @p path what @p rows writes (9 digits), the file begun
  /// afresh with the line @p header when @p first; throws std::runtime_error naming the
  /// file and @p what when a write fails.
  void
  append_trace_rows(const std::string &path, bool first, const std::string &header,
                    const std::function<void(std::ostream &)> &rows, const std::string &what);

  class SutureNewtonTrace
  {
  public:
    using PointStates = std::function<std::vector<coupling::TissueNeedle::ThreadPointState>()>;

    /// @p nodal: the suture's nodal terms by name, each evaluated as a part of its own;
    /// @p points: the pierce points on the thread at the current iterate (may be empty:
    /// then no points file).
    SutureNewtonTrace(std::vector<std::pair<std::string, const rod::NodalTerms *>> nodal, std::string file,
                      PointStates points = {});

    /// Records one iteration of the current solve (a new solve starts at iteration 0).
    void
    record(rod::RodModel &suture, const rod::NewtonIterate &iterate);

    /// Appends the current solve's iterations to the file and its points to the points
    /// file (the first call starts both afresh), labelled with the step's end time @p t
    /// and length @p dt; throws std::runtime_error naming the file when a write fails.
    /// The norms mix the nodes' forces (N) and moments (N m), as the suture's Newton
    /// solve does.
    void
    write(double t, double dt);

  private:
    struct Row
    {
      unsigned            iteration = 0;
      double              residual = 0, step = 0, moved = 0, turned = 0;
      std::vector<double> norms;       ///< each part's free norm
      std::size_t         worst = 0;   ///< the node with the largest free residual
      std::vector<double> worst_norms; ///< each part's norm at that node
      std::vector<coupling::TissueNeedle::ThreadPointState> points;
    };
    std::vector<std::string>                                      names;
    std::vector<std::pair<std::string, const rod::NodalTerms *>> nodal;
    std::string                                                   file;
    PointStates                                                   point_states;
    std::vector<Row>                                              rows;
    unsigned                                                      solves = 0;
  };
} // namespace suturesim::scene
