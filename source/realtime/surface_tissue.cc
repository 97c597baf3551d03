/**
 * The surface mass-spring tissue of seeds 001, 002 and 003: the tetrahedral mesh's
 * boundary triangles as a membrane (spring_set.h, linearised Delingette rule with
 * thickness t) held in shape by home springs (home_springs.h, Winkler rule
 * K_h = A_i E_oed/H_f). Why a membrane on a foundation: the surface model has no nodes
 * inside the body, so the body's resistance to indentation must come from the home
 * springs; for a layer of depth H_f on a rigid base under a uniform load that
 * resistance is exactly E_oed/H_f per unit area.
 * Where the needle touches it, the surface is subdivided (seed 002 §4.A,
 * surface_subdivision.h) from a pool of spare nodes set aside here.
 */
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/surface_subdivision.h>
#include <suturesim/realtime/tissue_model.h>

#include <Eigen/Geometry>

namespace suturesim::realtime
{
  namespace
  {
    class SurfaceTissue : public TissueModel
    {
    public:
      explicit SurfaceTissue(const ParameterValues &p)
        : thickness(p.real("Membrane thickness"))
        , rule(p.text("Home spring rule"))
        , depth(p.real("Foundation depth"))
        , home_stiffness(p.real("Home spring stiffness"))
      {
        subdivision.rest_length_factor = p.real("Subdivision rest length factor");
        subdivision.capacity = p.boolean("Subdivision") ? static_cast<unsigned>(p.integer("Subdivision capacity")) : 0;
        p.require(subdivision.rest_length_factor > 0, "Subdivision rest length factor", "must be > 0");
        bending_factor = p.real("Bending stiffness factor");
        bending_points = p.text("Bending points");
        p.require(rule != "constant" || home_stiffness > 0, "Home spring stiffness",
                  "must be > 0 N/m with Home spring rule = constant");
      }

    protected:
      void
      add_body(System &s, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &surface,
               const TissueMaterial &m, bool) override
      {
        if (!m.regions.empty())
          throw ParameterError("Tissue model", "'surface' has no volume to layer: Tissue/Region "
                                               "moduli needs Tissue model = volume");
        const Matrix3Xd &X = mesh.vertices;
        // nodal surface areas (a third of each triangle) and the body's volume
        std::vector<double> area(X.cols(), 0.0);
        double              total_area = 0, mean_edge = 0;
        for (const auto &t : surface.triangles)
          {
            const double a = 0.5 * (X.col(t[1]) - X.col(t[0])).cross(X.col(t[2]) - X.col(t[0])).norm();
            for (const auto v : t)
              area[v] += a / 3;
            total_area += a;
            for (unsigned k = 0; k < 3; ++k)
              mean_edge += (X.col(t[k]) - X.col(t[(k + 1) % 3])).norm();
          }
        mean_edge /= 3.0 * surface.triangles.size();
        const double volume = mesh.total_volume();

        for (const auto v : surface.vertices)
          node_of_vertex[v] = s.nodes.add(X.col(v), m.density * volume * area[v] / total_area, 0);

        std::vector<std::uint32_t> node(node_of_vertex.begin(), node_of_vertex.end());
        auto springs = std::make_unique<SpringSet>("tissue springs");
        add_membrane_springs(*springs, X, surface.triangles, node, m.youngs_modulus,
                             m.poisson_ratio, thickness > 0 ? thickness : mean_edge);
        springs->sort();

        auto         home = std::make_unique<HomeSprings>();
        const double nu   = m.poisson_ratio;
        const double oedometric =
          m.youngs_modulus * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
        const double H = depth > 0 ? depth
                                   : (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).minCoeff();
        for (const auto v : surface.vertices)
          home->add(node[v], X.col(v), rule == "winkler" ? area[v] * oedometric / H : home_stiffness);

        // Spare nodes for seed 002's subdivision, four per subdivision, after the surface's
        // (inside the tissue's node range, so that no index moves when they are taken):
        // held as dormant, with a negligible mass and home spring until then (both
        // are set from the surface's rules when a subdivision takes the node).
        const std::uint32_t spares = 4 * subdivision.capacity;
        if (spares > 0)
          {
            const double   mass_per_area = m.density * volume / total_area;
            const double   tiny_mass     = 1e-9 * mass_per_area * total_area / surface.vertices.size();
            const Vector3d parked        = X.col(surface.vertices.front());
            const auto     first         = s.nodes.size();
            for (std::uint32_t k = 0; k < spares; ++k)
              {
                const auto i = s.nodes.add(parked, tiny_mass, 0);
                s.nodes.set_held(i, Nodes::dormant, true);
                home->add(i, parked, 1e-9);
              }
            double longest = 0;
            for (const auto &t : surface.triangles)
              for (unsigned k = 0; k < 3; ++k)
                longest = std::max(longest, (X.col(t[k]) - X.col(t[(k + 1) % 3])).norm());
            const SurfaceLumping lumping{mass_per_area, rule == "winkler" ? oedometric / H : 0.0,
                                         rule == "winkler" ? 0.0 : home_stiffness};
            refiner = std::make_unique<SurfaceSubdivision>(subdivision, *springs, *home, first, lumping, longest);
          }
        s.interactions.push_back(std::move(springs));
        s.interactions.push_back(std::move(home));
      }

    public:
      std::int64_t
      subdivide(System &s, const std::uint32_t triangle, const Vector3d &weights) override
      {
        return refiner ? refiner->subdivide(s, mutable_surface(), mutable_surface_tags(), triangle, weights) : -1;
      }

    private:
      double                              thickness;
      std::string                         rule;
      double                              depth, home_stiffness;
      SubdivisionParameters               subdivision;
      std::unique_ptr<SurfaceSubdivision> refiner;
    };

    const bool registered = TissueModel::Registry::instance().add(
      {"surface",
       "the boundary triangles as a mass-spring membrane with home springs (seeds 001, 002, "
       "003): k_e = sum E t L^2 (2 cot^2 theta + 1 - nu)/(8 (1 - nu^2) A) (Delingette 2008, "
       "linearised), home springs K_h = A_i E(1-nu)/((1+nu)(1-2nu) H_f) (Winkler).",
       [](ParameterDeclarations &d) {
         d.add_real("Membrane thickness", 0, 0, 1,
                    "Thickness t of the membrane in the spring rule; 0 = the mean surface "
                    "edge length. Unit: m. Range: >= 0.");
         d.add_selection("Home spring rule", "winkler", "winkler|constant",
                         "'winkler': K_h = A_i E_oed / H_f (foundation of depth H_f); "
                         "'constant': every node gets Home spring stiffness.");
         d.add_real("Foundation depth", 0, 0, 10,
                    "H_f of the Winkler rule; 0 = the smallest extent of the mesh's bounding "
                    "box. Unit: m. Range: >= 0.");
         d.add_real("Home spring stiffness", 0, 0, 1e12,
                    "K_h of every node with Home spring rule = constant. Unit: N/m. Range: > 0.");
         d.add_bool("Subdivision", true,
                    "Seed 002 sec. 4.A: where the needle touches the surface, the touched "
                    "triangle is subdivided (a new vertex at the point, Loop's edge mask on "
                    "its edges) and the pierce point is that vertex. Unit: none.");
         d.add_real("Subdivision rest length factor", 0.9, 0, 1,
                    "Rest length of the subdivided patch's springs over their length at "
                    "creation (seed 002: 0.9, to put the patch under tension; 1: stress-free). "
                    "Unit: 1. Range: (0, 1].");
         d.add_integer("Subdivision capacity", 16, 0, 1024,
                       "Subdivisions a run may make (spare nodes are set aside for them, four "
                       "each); past it a touch stays a point of its triangle. Unit: 1. "
                       "Range: 0-1024.");
         declare_bending_parameters(d);
       },
       [](const ParameterValues &p) { return std::unique_ptr<TissueModel>(new SurfaceTissue(p)); }});
  } // namespace
} // namespace suturesim::realtime
