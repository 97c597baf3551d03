/**
 * The volumetric mass-spring tissue (seed 004's tetrahedral model): a spring on every
 * tetrahedron edge, masses ρV/4 per tetrahedron and vertex, and, under XPBD, one volume
 * constraint per tetrahedron carrying the bulk stiffness the springs lack
 * (volume_constraints.h), so that the network's response to a uniform dilatation is the
 * continuum's K. Three spring laws (`Spring law`):
 *  - "van gelder" (default): k_e = E Σ V_T / L_e² (spring_set.h), a network of bulk
 *    modulus 2E/3 on any mesh; the constraints carry K − 2E/3;
 *  - "lloyd" and "least squares": the constants identified from the linear FE element
 *    for the material's shear modulus μ (Lloyd, Székely & Harders 2007: their closed
 *    form, or each tetrahedron's least-squares match; spring_identification.h); the
 *    constraints carry K minus the network's own bulk modulus, per tetrahedron.
 *
 * Two multipliers make those rules a starting point for calibration (issue 28,
 * docs/calibration.md): `Spring stiffness scale` s_k multiplies every spring's k_e, and
 * `Volume stiffness scale` s_V every tetrahedron's constraint stiffness; both 1 by
 * default, the physically derived values.
 */
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_identification.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/realtime/volume_constraints.h>

#include <algorithm>

namespace suturesim::realtime
{
  namespace
  {
    class VolumeTissue : public TissueModel
    {
    public:
      explicit VolumeTissue(const ParameterValues &p)
        : volume_mode(p.text("Volume constraints"))
        , spring_law(p.text("Spring law"))
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
        const Matrix3Xd                 &X    = mesh.vertices;
        const std::vector<std::uint32_t> node = add_tetrahedral_nodes(s, mesh, m.density);

        auto                      springs = std::make_unique<SpringSet>("tissue springs");
        const std::vector<double> bulk    = add_springs(*springs, mesh, node, m);
        const bool all_bulk = std::all_of(bulk.begin(), bulk.end(), [](const double b) { return b > 0; });
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
      }

    private:
      /// The springs of the Spring law; returns each tetrahedron's bulk stiffness for the
      /// volume constraints, s_V (K − the springs' own bulk modulus: 2E/3 for Van Gelder's
      /// rule on any mesh, network_bulk_modulus() for the identified laws).
      std::vector<double>
      add_springs(SpringSet &springs, const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                  const TissueMaterial &m) const
      {
        // per tetrahedron: the springs' modulus (E for Van Gelder's rule, μ for the
        // identified laws; k_e is linear in it) and K
        const bool          identified = spring_law != "van gelder";
        const std::size_t   n          = mesh.tetrahedra.size();
        std::vector<double> modulus(n), K(n), network_bulk(n);
        for (std::size_t t = 0; t < n; ++t)
          {
            const int    tag = t < mesh.tetrahedron_tags.size() ? mesh.tetrahedron_tags[t] : 0;
            K[t]             = m.bulk_modulus_of(tag);
            modulus[t]       = identified ? m.shear_modulus_of(tag) : m.youngs_modulus_of(tag);
          }
        if (identified)
          network_bulk = add_identified_volume_springs(springs, mesh, node, spring_law, modulus, spring_scale);
        else
          {
            std::vector<double> scaled(n);
            for (std::size_t t = 0; t < n; ++t)
              {
                network_bulk[t] = 2 * modulus[t] / 3;
                scaled[t]       = spring_scale * modulus[t];
              }
            add_volume_springs(springs, mesh, node, scaled);
          }
        std::vector<double> bulk(n);
        for (std::size_t t = 0; t < n; ++t)
          bulk[t] = volume_scale * (K[t] - network_bulk[t]);
        return bulk;
      }

      std::string volume_mode;
      std::string spring_law;
      double      home_stiffness, spring_scale, volume_scale;
    };

    const bool registered = TissueModel::Registry::instance().add(
      {"volume",
       "a spring on every tetrahedron edge (Van Gelder's rule or identified from the "
       "linear FE element), with volume constraints carrying the bulk stiffness the "
       "springs lack under XPBD (seed 004).",
       [](ParameterDeclarations &d) {
         d.add_selection("Spring law", "van gelder", "van gelder|lloyd|least squares",
                         "The tissue springs' constants: 'van gelder', k_e = E sum V_T / "
                         "L_e^2 (Van Gelder 1998; volume constraints K - 2E/3); 'lloyd', "
                         "(sqrt 2/5) mu l per tetrahedron of equivalent edge l = (12V/sqrt "
                         "2)^(1/3) (Lloyd, Szekely & Harders 2007); 'least squares', each "
                         "tetrahedron's six constants matching its linear FE stiffness "
                         "matrix for the shear modulus mu best (their criterion); the "
                         "identified laws' volume constraints carry K minus the springs' "
                         "own bulk modulus.");
         d.add_selection("Volume constraints", "auto", "auto|on|off",
                         "Tetrahedron volume constraints (the bulk stiffness the springs "
                         "lack, see Spring law): 'auto' "
                         "adds them under XPBD only, so that the force-based integrators "
                         "see the springs alone (bulk modulus 2E/3, nu = 1/4 with Van "
                         "Gelder's rule); 'on' also as forces for the force-based "
                         "integrators (stiffer: the quasi-static step on 1 mm tetrahedra of "
                         "skin then needs about 12 kHz, docs/calibration.md); 'off' never.");
         d.add_real("Home spring stiffness", 0, 0, 1e12,
                    "Home springs on every node (seed 001 sec. 2.1); 0 = none. Unit: N/m. "
                    "Range: >= 0.");
         d.add_real("Spring stiffness scale", 1, 1e-3, 1e3,
                    "Multiplies every tissue spring's stiffness from its Spring law (a "
                    "calibration parameter, docs/calibration.md). Unit: 1. Range: [1e-3, "
                    "1e3].");
         d.add_real("Volume stiffness scale", 1, 1e-3, 1e3,
                    "Multiplies every volume constraint's bulk stiffness (K - 2E/3 or K - "
                    "5mu/3, see Spring law; a calibration parameter, docs/calibration.md). "
                    "Unit: 1. Range: [1e-3, 1e3].");
         declare_bending_parameters(d);
       },
       [](const ParameterValues &p) { return std::unique_ptr<TissueModel>(new VolumeTissue(p)); }});
  } // namespace
} // namespace suturesim::realtime
