// The .vtu files read back (tests/unit/vtu_reader.h): the fields README's output table
// names, their sizes, and values checked against the run's own summary.json and
// forces.csv and against the mechanics (a fixed face does not move; a rod loaded at its
// end alone carries that load through every section). The files store Float32, so
// values agree to its rounding (2^-24 = 6e-8 relative).
#include "run_scene.h"
#include "vtu_reader.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>

using namespace suturesim::test_support;

namespace
{
  constexpr double float_rounding = 1.2e-7; // two roundings to Float32

  /// The row of @p rows whose time is nearest @p t.
  const std::vector<double> &
  row_at(const std::vector<std::vector<double>> &rows, const double t)
  {
    std::size_t best = 0;
    for (std::size_t k = 1; k < rows.size(); ++k)
      if (std::abs(rows[k][0] - t) < std::abs(rows[best][0] - t))
        best = k;
    return rows[best];
  }

} // namespace

TEST(VtuOutput, AccurateTissueFilesHoldTheDocumentedFieldsOnTheReferenceMesh)
{
  // tests/data/cook_coarse.prm: Cook's membrane, 2 x 2 x 1 Q1 cells, left face clamped,
  // outputs at t = 0, 0.5, 1
  const auto r = run_suturesim("vtu_cook", {source_path("tests/data/cook_coarse.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Vtu first = read_vtu(r.directory + "/tissue_00000.vtu");
  const Vtu last  = read_vtu(r.directory + "/tissue_00002.vtu");
  // one patch of 8 vertices a Q1 cell
  EXPECT_EQ(last.n_cells, 4u);
  EXPECT_EQ(last.n_points, 32u);
  EXPECT_EQ(last.get("FieldData", "TIME").values.at(0), 1.0);
  // README: displacement, Cauchy stress (tensor), von Mises stress, J, largest principal
  // stretch, pressure, material id, MPI rank
  EXPECT_EQ(last.names("PointData"),
            (std::vector<std::string>{"displacement", "cauchy_stress", "von_mises_stress", "J",
                                      "max_principal_stretch", "pressure", "material_id", "mpi_rank"}));
  const std::map<std::string, unsigned> components{{"displacement", 3}, {"cauchy_stress", 9}};
  for (const auto &a : last.arrays)
    if (a.section == "PointData")
      {
        EXPECT_EQ(a.components, components.count(a.name) ? components.at(a.name) : 1u) << a.name;
        EXPECT_EQ(a.tuples(), last.n_points) << a.name;
      }
  // the reference mesh: the same points at every output
  EXPECT_EQ(last.points().values, first.points().values);
  const auto &X = last.points().values, &u = last.get("PointData", "displacement").values;
  // the clamped face x = 0 does not move; the tip (48, 60, 0.5) mm is the probe
  const auto  &m = r.summary["metrics"];
  unsigned     clamped = 0, tips = 0;
  double       largest = 0;
  for (std::size_t p = 0; p < last.n_points; ++p)
    {
      largest = std::max(largest, std::hypot(u[3 * p], u[3 * p + 1], u[3 * p + 2]));
      if (X[3 * p] == 0)
        {
          for (unsigned d = 0; d < 3; ++d)
            EXPECT_EQ(u[3 * p + d], 0.0) << "point " << p;
          ++clamped;
        }
      if (std::abs(X[3 * p] - 0.048) < 1e-8 && std::abs(X[3 * p + 1] - 0.060) < 1e-8 &&
          std::abs(X[3 * p + 2] - 0.0005) < 1e-8)
        {
          for (unsigned d = 0; d < 3; ++d)
            EXPECT_NEAR(u[3 * p + d], m["tip_displacement_" + std::string(1, char('x' + d))].get<double>(),
                        float_rounding * largest + 1e-12)
              << "component " << d;
          ++tips;
        }
    }
  EXPECT_EQ(clamped, 8u); // 2 cells on the face, 4 of their vertices each
  EXPECT_EQ(tips, 1u);
  EXPECT_GT(largest, 1e-3); // the membrane's tip moves millimetres
  // J is det F, > 0; the cell data (material id, MPI rank) one value a cell, on all
  // of its patch's 8 points; one MPI rank
  for (const double J : last.get("PointData", "J").values)
    EXPECT_GT(J, 0);
  const auto &material = last.get("PointData", "material_id").values;
  for (std::size_t p = 0; p < last.n_points; ++p)
    {
      EXPECT_EQ(material[p], material[8 * (p / 8)]) << "point " << p;
      EXPECT_EQ(material[p], std::round(material[p])) << "point " << p;
    }
  for (const double v : last.get("PointData", "mpi_rank").values)
    EXPECT_EQ(v, 0.0);
}

TEST(VtuOutput, RealtimeFilesHoldTheDeformedTissueAndTheThreadsTension)
{
  // the default stitch to 2.6 s (the thread drawn through its four holes, its tail
  // grasped: tension at both ends), with a probe inside side A; outputs every 0.1 s
  const auto r = run_suturesim("vtu_realtime", {source_path("parameters/stitch_interrupted.prm"), "--set",
                                                "Time/End time=2.6", "--set",
                                                "Tissue/Probes=inside: -0.003, 0.002, 0.004"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string header;
  const auto  rows = read_forces(r, &header);
  ASSERT_FALSE(rows.empty());
  const Vtu first = read_vtu(r.directory + "/tissue_00000.vtu");
  const Vtu last  = read_vtu(r.directory + "/tissue_00026.vtu");
  const double t  = last.get("FieldData", "TIME").values.at(0);
  EXPECT_NEAR(t, 2.6, 1e-6);
  // tetrahedra on shared points: one point per tissue node (io/simplex_writer.h)
  EXPECT_EQ(last.n_points, r.summary["mesh"]["vertices"].get<std::size_t>());
  EXPECT_GT(last.n_cells, 1000u);
  const auto &connectivity = last.get("Cells", "connectivity").values;
  ASSERT_EQ(connectivity.size(), 4 * last.n_cells);
  EXPECT_EQ(last.get("Cells", "offsets").values.back(), double(4 * last.n_cells));
  for (const double type : last.get("Cells", "types").values)
    ASSERT_EQ(type, 10.0); // VTK_TETRA
  for (const double p : connectivity)
    ASSERT_LT(p, double(last.n_points));
  EXPECT_EQ(first.get("Cells", "connectivity").values, connectivity);
  EXPECT_EQ(last.names("PointData"), (std::vector<std::string>{"displacement", "velocity"}));
  for (const auto &a : last.arrays)
    if (a.section == "PointData")
      {
        EXPECT_EQ(a.components, 3u) << a.name;
        EXPECT_EQ(a.tuples(), last.n_points) << a.name;
      }
  // deformed positions: points − displacement is the reference mesh, as at t = 0
  const auto &x = last.points().values, &u = last.get("PointData", "displacement").values,
             &X = first.points().values;
  ASSERT_EQ(X.size(), x.size());
  double largest = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    {
      // three Float32 roundings of coordinates below 0.03 m
      EXPECT_NEAR(x[k] - u[k], X[k], 3 * float_rounding * 0.03) << "coordinate " << k;
      largest = std::max(largest, std::abs(u[k]));
    }
  EXPECT_GT(largest, 1e-5);
  // the fixed bottom (z = 0) has not moved; the probe is the barycentric interpolation
  // of the displacement in its tetrahedron (realtime/world.h add_probe())
  const auto &probe = row_at(rows, t);
  unsigned    bottom = 0, inside = 0;
  for (std::size_t c = 0; c < last.n_cells; ++c)
    {
      Eigen::Matrix<double, 3, 4> corners, displacement;
      for (unsigned v = 0; v < 4; ++v)
        for (unsigned d = 0; d < 3; ++d)
          {
            const auto p       = static_cast<std::size_t>(connectivity[4 * c + v]);
            corners(d, v)      = X[3 * p + d];
            displacement(d, v) = u[3 * p + d];
          }
      for (unsigned v = 0; v < 4; ++v)
        if (corners(2, v) == 0)
          {
            EXPECT_EQ(displacement.col(v).norm(), 0.0) << "cell " << c;
            ++bottom;
          }
      Eigen::Matrix3d A;
      A << corners.col(1) - corners.col(0), corners.col(2) - corners.col(0), corners.col(3) - corners.col(0);
      const Eigen::Vector3d xi = A.partialPivLu().solve(Eigen::Vector3d(-0.003, 0.002, 0.004) - corners.col(0));
      if (xi.minCoeff() < -1e-6 || xi.sum() > 1 + 1e-6)
        continue;
      const Eigen::Vector4d w(1 - xi.sum(), xi[0], xi[1], xi[2]);
      const Eigen::Vector3d at = displacement * w;
      for (unsigned d = 0; d < 3; ++d)
        EXPECT_NEAR(at[d], probe[column(header, "inside_displacement_" + std::string(1, char('x' + d)))],
                    1e-6 * at.norm() + 1e-12)
          << "component " << d;
      ++inside;
    }
  EXPECT_GT(bottom, 0u);
  EXPECT_GE(inside, 1u); // on a shared face or edge, in each cell around it

  // the suture: one segment a patch of two points, its radius (3-0 monofilament) and
  // its tension, which is forces.csv's at the swage (the needle holds the first two
  // nodes: the first segment it does not hold, scene/realtime_needle.cc) and at the end
  const Vtu suture = read_vtu(r.directory + "/suture_00026.vtu");
  EXPECT_EQ(suture.names("PointData"), (std::vector<std::string>{"radius", "tension"}));
  EXPECT_EQ(suture.n_points, 2 * suture.n_cells);
  EXPECT_EQ(suture.n_cells + 1, r.summary["suture"]["nodes"].get<std::size_t>());
  for (const double radius : suture.get("PointData", "radius").values)
    EXPECT_NEAR(radius, 0.11225e-3, 0.11225e-3 * float_rounding);
  const auto  &tension = suture.get("PointData", "tension").values;
  const double swage = probe[column(header, "suture_tension_swage")], end = probe[column(header, "suture_tension_free_end")];
  std::printf("[ vtu ] t = %.3f s: tension at the swage %.6e N (forces.csv %.6e N), at the end %.6e N (%.6e N)\n", t,
              tension[2], swage, tension.back(), end);
  EXPECT_GT(swage, 1.0); // the needle draws the thread through its holes
  EXPECT_GT(end, 0.1);   // against the grasper on its tail
  EXPECT_LT(std::abs(tension[0]), 1e-9 * swage); // the held segment
  for (const std::size_t point : {2, 3})         // both points of segment 1
    EXPECT_NEAR(tension[point], swage, float_rounding * swage);
  EXPECT_NEAR(tension.back(), end, float_rounding * end);
}

TEST(VtuOutput, RodFilesHoldSectionForcesThatCarryTheEndLoad)
{
  // benchmarks/rod_cantilever/rod_cantilever.prm: clamped at x = 0, the end force
  // P = (0, −0.0442, 0) N alone; every section carries P (statics of the cut-off part:
  // its resultant in the section's frame, axial² + shear² = |P|², whatever the
  // deflection), the tip is metrics.tip_position, contact forces are zero
  const auto r = run_suturesim("vtu_rod", {benchmark_scene("rod_cantilever")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Vtu rod = read_vtu(r.directory + "/suture_00005.vtu");
  EXPECT_NEAR(rod.get("FieldData", "TIME").values.at(0), 1.0, 1e-7);
  EXPECT_EQ(rod.names("PointData"), (std::vector<std::string>{"radius", "contact_force", "axial_force", "shear_force",
                                                              "bending_moment", "twisting_moment", "twist",
                                                              "curvature"}));
  EXPECT_EQ(rod.n_cells, 32u);
  EXPECT_EQ(rod.n_points, 64u);
  const double P = 0.04417865;
  const auto  &axial = rod.get("PointData", "axial_force").values, &shear = rod.get("PointData", "shear_force").values;
  for (std::size_t p = 0; p < rod.n_points; ++p)
    {
      // measured 4e-8 (Float32 and Newton's tolerance)
      EXPECT_NEAR(std::hypot(axial[p], shear[p]), P, 1e-6 * P) << "point " << p;
      EXPECT_EQ(rod.get("PointData", "contact_force").values[p], 0.0);
      EXPECT_NEAR(rod.get("PointData", "radius").values[p], 0.5e-3, 0.5e-3 * float_rounding);
    }
  // large deflection: the section at the clamp turns the load into shear, the end's
  // into tension
  EXPECT_GT(shear.front(), 0.9 * P);
  EXPECT_GT(axial.back(), 0.5 * P);
  const auto &x   = rod.points().values;
  const auto &tip = r.summary["metrics"]["tip_position"];
  for (unsigned d = 0; d < 3; ++d)
    EXPECT_NEAR(x[x.size() - 3 + d], tip[d].get<double>(), float_rounding * 0.1) << d; // |x| < 0.1 m
}
