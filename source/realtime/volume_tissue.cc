/**
 * The volumetric mass-spring tissue (seed 004's tetrahedral model): a spring on every
 * tetrahedron edge (Van Gelder's rule, spring_set.h), masses ρV/4 per tetrahedron and
 * vertex, and, under XPBD, one volume constraint per tetrahedron carrying the bulk
 * stiffness K − 2E/3 that the springs lack (volume_constraints.h), so that the
 * network's response to a uniform dilatation is the continuum's K.
 *
 * Two multipliers make those rules a starting point for calibration (issue 28,
 * docs/calibration.md): `Spring stiffness scale` s_k multiplies every spring's k_e, and
 * `Volume stiffness scale` s_V every tetrahedron's bulk stiffness K − 2E/3; both 1 by
 * default, the physically derived values.
 */
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/realtime/volume_constraints.h>

namespace suturesim::realtime
{
  namespace
  {
    class VolumeTissue : public TissueModel
    {
    public:
      explicit VolumeTissue(const ParameterValues &p)
        : volume_mode(p.text("Volume constraints"))
        , home_stiffness(p.real("Home spring stiffness"))
        , spring_scale(p.real("Spring stiffness scale"))
        , volume_scale(p.real("Volume stiffness scale"))
      {
        bending_factor = p.real("Bending stiffness factor");
        bending_points = p.text("Bending points");
      }

    protected:
      void
      add_body(System &s, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &,
               const TissueMaterial &m, const bool position_based) override
      {
        const Matrix3Xd    &X = mesh.vertices;
        std::vector<double> mass(X.cols(), 0.0);
        for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
          for (const auto v : mesh.tetrahedra[t])
            mass[v] += m.density * mesh.volume(t) / 4;
        for (Eigen::Index v = 0; v < X.cols(); ++v)
          if (mass[v] > 0) // vertices of no tetrahedron (stray gmsh points) are left out
            node_of_vertex[v] = s.nodes.add(X.col(v), mass[v], 0);
        std::vector<std::uint32_t> node(node_of_vertex.begin(), node_of_vertex.end());

        auto springs = std::make_unique<SpringSet>("tissue springs");
        // per tetrahedron: E, and the bulk stiffness K − 2E/3 the springs lack
        std::vector<double> E(mesh.tetrahedra.size()), bulk(mesh.tetrahedra.size());
        bool                all_bulk = true;
        for (std::size_t t = 0; t < E.size(); ++t)
          {
            const int tag = t < mesh.tetrahedron_tags.size() ? mesh.tetrahedron_tags[t] : 0;
            const double e = m.youngs_modulus_of(tag);
            E[t]           = spring_scale * e; // k_e is linear in E (Van Gelder's rule)
            bulk[t]        = volume_scale * (m.bulk_modulus_of(tag) - 2 * e / 3);
            all_bulk       = all_bulk && bulk[t] > 0;
          }
        add_volume_springs(*springs, mesh, node, E);
        springs->sort();
        s.interactions.push_back(std::move(springs));

        if ((volume_mode == "on" || (volume_mode == "auto" && position_based)) && all_bulk)
          {
            auto volumes = std::make_unique<VolumeConstraints>();
            volumes->add_mesh(mesh, node, bulk);
            s.interactions.push_back(std::move(volumes));
          }
        if (home_stiffness > 0)
          {
            auto home = std::make_unique<HomeSprings>();
            for (Eigen::Index v = 0; v < X.cols(); ++v)
              if (node_of_vertex[v] >= 0)
                home->add(node[v], X.col(v), home_stiffness);
            s.interactions.push_back(std::move(home));
          }
        cells.clear();
        for (const auto &t : mesh.tetrahedra)
          cells.push_back({node[t[0]], node[t[1]], node[t[2]], node[t[3]]});
      }

    private:
      std::string volume_mode;
      double      home_stiffness, spring_scale, volume_scale;
    };

    const bool registered = TissueModel::Registry::instance().add(
      {"volume",
       "a spring on every tetrahedron edge, k_e = E sum V_T / L_e^2 (Van Gelder 1998), "
       "with volume constraints of bulk stiffness K - 2E/3 under XPBD (seed 004).",
       [](ParameterDeclarations &d) {
         d.add_selection("Volume constraints", "auto", "auto|on|off",
                         "Tetrahedron volume constraints (bulk stiffness K - 2E/3): 'auto' "
                         "adds them under XPBD only, 'on' also as forces for the force-based "
                         "integrators, 'off' never.");
         d.add_real("Home spring stiffness", 0, 0, 1e12,
                    "Home springs on every node (seed 001 sec. 2.1); 0 = none. Unit: N/m. "
                    "Range: >= 0.");
         d.add_real("Spring stiffness scale", 1, 1e-3, 1e3,
                    "Multiplies every tissue spring's Van Gelder stiffness k_e = E sum V_T / "
                    "L_e^2 (a calibration parameter, docs/calibration.md). Unit: 1. Range: "
                    "[1e-3, 1e3].");
         d.add_real("Volume stiffness scale", 1, 1e-3, 1e3,
                    "Multiplies every volume constraint's bulk stiffness K - 2E/3 (a "
                    "calibration parameter, docs/calibration.md). Unit: 1. Range: [1e-3, "
                    "1e3].");
         declare_bending_parameters(d);
       },
       [](const ParameterValues &p) { return std::unique_ptr<TissueModel>(new VolumeTissue(p)); }});
  } // namespace
} // namespace suturesim::realtime
