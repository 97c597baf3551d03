/**
 * The finite-element tissue of the realtime path: the gmsh mesh's linear tetrahedra with
 * the stable neo-Hookean energy (neo_hookean_tetrahedra.h), masses ρV/4 per tetrahedron
 * and vertex. Its Lamé constants are the material's own (μ = 3KE/(9K − E), λ = K − 2μ/3
 * per region), so that its small-strain response is the accurate path's material
 * discretised by linear elements: it converges to the continuum under refinement, which
 * no spring network does (docs/calibration.md). The force-based integrators see its
 * forces, VBD its exact vertex blocks; XPBD is refused (neo_hookean_tetrahedra.h says
 * why). Two multipliers of μ and K are calibration parameters, 1 as derived.
 *
 * `Volumetric energy = nodal` moves the bulk term λ/2 (J − 1)² from each element to each
 * node's patch (Bonet & Burton's average nodal pressure, nodal_volumes.h), against the
 * volumetric locking of linear tetrahedra as ν → ½; the elements keep μ (λ = 0).
 */
#include <suturesim/realtime/neo_hookean_tetrahedra.h>
#include <suturesim/realtime/nodal_volumes.h>
#include <suturesim/realtime/tissue_model.h>

namespace suturesim::realtime
{
  namespace
  {
    class FeTissue : public TissueModel
    {
    public:
      explicit FeTissue(const ParameterValues &p)
          : shear_scale(p.real("Shear stiffness scale"))
          , bulk_scale(p.real("Bulk stiffness scale"))
          , nodal(p.text("Volumetric energy") == "nodal")
      {
      }

    protected:
      void
      add_body(System &s, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &, const TissueMaterial &m,
               bool) override
      {
        const std::vector<std::uint32_t> node = add_tetrahedral_nodes(s, mesh, m.density);
        const std::size_t                n    = mesh.tetrahedra.size();
        std::vector<double>              mu(n), lambda(n);
        for (std::size_t t = 0; t < n; ++t)
          {
            const int tag = t < mesh.tetrahedron_tags.size() ? mesh.tetrahedron_tags[t] : 0;
            mu[t]         = shear_scale * m.shear_modulus_of(tag);
            lambda[t]     = bulk_scale * m.bulk_modulus_of(tag) - 2 * mu[t] / 3;
            if (!(lambda[t] > 0))
              throw ParameterError("Bulk stiffness scale",
                                   "leaves lambda = s_K K - 2 s_mu mu/3 <= 0 (Poisson's ratio <= 0)");
          }
        auto elements = std::make_unique<NeoHookeanTetrahedra>();
        elements->add_mesh(mesh, node, mu, nodal ? std::vector<double>(n, 0.0) : lambda);
        s.interactions.push_back(std::move(elements));
        if (nodal)
          {
            auto volumes = std::make_unique<NodalVolumes>();
            volumes->add_mesh(mesh, node, lambda);
            s.interactions.push_back(std::move(volumes));
          }
      }

    private:
      double shear_scale, bulk_scale;
      bool   nodal;
    };

    const bool registered = TissueModel::Registry::instance().add(
        { "fe",
          "linear tetrahedral finite elements with the stable neo-Hookean energy (Smith et al. "
          "2018), the material's own Lame constants: converges to the continuum under "
          "refinement; under the force-based integrators and vbd, not xpbd.",
          [](ParameterDeclarations &d) {
            d.add_real("Shear stiffness scale", 1, 1e-3, 1e3,
                       "Multiplies the shear modulus mu = 3KE/(9K - E) of every tetrahedron (a "
                       "calibration parameter; 1 = the material's). Unit: 1. Range: [1e-3, 1e3].");
            d.add_real("Bulk stiffness scale", 1, 1e-3, 1e3,
                       "Multiplies the bulk modulus K = lambda + 2mu/3 of every tetrahedron (a "
                       "calibration parameter; 1 = the material's). Unit: 1. Range: [1e-3, 1e3].");
            d.add_selection("Volumetric energy", "element", "element|nodal",
                            "Where the bulk term lambda/2 (J - 1)^2 is evaluated: 'element', J of each "
                            "tetrahedron (linear tetrahedra lock as nu -> 1/2); 'nodal', J of each node's "
                            "patch, Bonet & Burton's (1998) average nodal pressure, which does not lock; "
                            "the elements then keep the shear modulus only. Unit: none.");
          },
          [](const ParameterValues &p) { return std::unique_ptr<TissueModel>(new FeTissue(p)); } });
  } // namespace
} // namespace suturesim::realtime
