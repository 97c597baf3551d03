/**
 * The surface mass-spring tissue of seeds 001, 002 and 003: the tetrahedral mesh's
 * boundary triangles as a membrane (spring_set.h, linearised Delingette rule with
 * thickness t) held in shape by home springs (home_springs.h, Winkler rule
 * K_h = A_i E_oed/H_f). Why a membrane on a foundation: the surface model has no nodes
 * inside the body, so the body's resistance to indentation must come from the home
 * springs; for a layer of depth H_f on a rigid base under a uniform load that
 * resistance is exactly E_oed/H_f per unit area.
 */
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
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
        double volume = 0;
        for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
          volume += mesh.volume(t);

        for (const auto v : surface.vertices)
          node_of_vertex[v] = s.nodes.add(X.col(v), m.density * volume * area[v] / total_area, 0);

        std::vector<std::uint32_t> node(node_of_vertex.begin(), node_of_vertex.end());
        auto springs = std::make_unique<SpringSet>("tissue springs");
        add_membrane_springs(*springs, X, surface.triangles, node, m.youngs_modulus,
                             m.poisson_ratio, thickness > 0 ? thickness : mean_edge);
        springs->sort();
        s.interactions.push_back(std::move(springs));

        auto         home = std::make_unique<HomeSprings>();
        const double nu   = m.poisson_ratio;
        const double oedometric =
          m.youngs_modulus * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
        const double H = depth > 0 ? depth
                                   : (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).minCoeff();
        for (const auto v : surface.vertices)
          home->add(node[v], X.col(v), rule == "winkler" ? area[v] * oedometric / H : home_stiffness);
        s.interactions.push_back(std::move(home));
      }

    private:
      double      thickness;
      std::string rule;
      double      depth, home_stiffness;
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
         declare_bending_parameters(d);
       },
       [](const ParameterValues &p) { return std::unique_ptr<TissueModel>(new SurfaceTissue(p)); }});
  } // namespace
} // namespace suturesim::realtime
