/**
 * A fracture specimen broken by phase-field fracture (Model = accurate, Bodies =
 * fracture specimen): the verification case of tearing/phase_field.h. The specimen is
 * the single-edge-notched tension plate (SENT) in plane strain: width W, height 2H, a
 * sharp notch (a slit of two free faces) of length a from the left edge at mid-height,
 * the top and bottom edges under a uniform traction ±σ e_y (free to rotate; rigid
 * motions removed at the right edge without reaction). The load rises by Load increment
 * until the crack runs (its tip passes Runaway length beyond the notch), and the critical
 * load is then bracketed by bisection, each trial from the last stable state.
 *
 * Reference: linear elastic fracture mechanics with the discretised crack's toughness,
 *   σ_c = √(E' G_eff / (π a)) / F(a/W),   E' = E / (1 − ν²),
 *   F(α) = 1.12 − 0.231 α + 10.55 α² − 21.72 α³ + 30.39 α⁴
 * (the long strip's shape factor, better than 0.5 % for α ≤ 0.6: Tada, Paris & Irwin, The
 * Stress Analysis of Cracks Handbook, 3rd ed., ASME 2000, §2.10 after Gross, Srawley &
 * Brown 1964), G_eff = G_c (1 + 3 h / (8 ℓ)) with h the cell size along the crack path.
 * AT1 matches LEFM in the limit ℓ ≪ a (Tanné, Li, Bourdin, Marigo & Maurini, J Mech Phys
 * Solids 110:80, 2018).
 */
#include <suturesim/core/error.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/timed_run.h>
#include <suturesim/tearing/phase_field.h>

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    constexpr types::boundary_id left = 0, right = 1, bottom = 2, top = 3, notch_faces = 4;

    struct Specimen
    {
      double   width = 0, height = 0, notch = 0;
      unsigned cells_across = 0, refinements = 0;
      double   band = 0;
      double   load_increment = 0, maximum_load = 0, bisection = 0, runaway = 0;
      tearing::PhaseFieldParameters material;

      static void
      declare(ParameterHandler &prm)
      {
        prm.enter_subsection("Fracture specimen");
        prm.declare_entry("Specimen", "single-edge-notched tension", Patterns::Selection("single-edge-notched tension"),
                          "The specimen (plane strain): a plate of Width x Height with a sharp notch of Notch length "
                          "from its left edge at mid-height, pulled by a uniform traction on its top and bottom edges.");
        prm.declare_entry("Width", "0.01", Patterns::Double(0), "W. Unit: m. Range: > 0.");
        prm.declare_entry("Height", "0.04", Patterns::Double(0), "2H, the whole height. Unit: m. Range: >= Width.");
        prm.declare_entry("Notch length", "0.003", Patterns::Double(0),
                          "a, a whole number of coarse cells. Unit: m. Range: (0, 0.6 Width] (the reference's range).");
        prm.declare_entry("Coarse cells across", "10", Patterns::Integer(2, 1000),
                          "Square coarse cells across the width. Unit: 1. Range: 2-1000; Height and Notch length must "
                          "be whole numbers of them.");
        prm.declare_entry("Path refinements", "6", Patterns::Integer(0, 12),
                          "Times the cells within Path half-width of the crack line (y = 0) are halved. Unit: 1. "
                          "Range: 0-12.");
        prm.declare_entry("Path half-width", "2e-4", Patterns::Double(0),
                          "Half-width of the refined band around the crack line. Unit: m. Range: > 0.");
        prm.declare_entry("Young's modulus", "6.5e6", Patterns::Double(0),
                          "E; default the stitch's skin (E of its mu and kappa). Unit: Pa. Range: > 0.");
        prm.declare_entry("Poisson's ratio", "0.3", Patterns::Double(0, 0.4999),
                          "nu. Unit: 1. Range: [0, 0.4999].");
        prm.declare_entry("Fracture toughness", "1.1e3", Patterns::Double(0),
                          "G_c; default porcine skin cut by a needle (1.1 kJ/m^2, as Tearing/fracture-energy). Unit: "
                          "J/m^2. Range: > 0.");
        prm.declare_entry("Internal length", "6e-5", Patterns::Double(0),
                          "l of AT1 (the Tearing/Process zone radius of the onset criterion). Unit: m. Range: > 0.");
        prm.declare_entry("Staggered tolerance", "1e-4", Patterns::Double(0),
                          "The alternate minimisation stops when no damage value changes by more. Unit: 1. Range: > 0.");
        prm.declare_entry("Staggered iterations", "1000", Patterns::Integer(1),
                          "The most alternate-minimisation iterations of one load. Unit: 1. Range: >= 1.");
        prm.declare_entry("Load increment", "2e4", Patterns::Double(0),
                          "The traction's step until the crack runs. Unit: Pa. Range: > 0.");
        prm.declare_entry("Maximum load", "1e6", Patterns::Double(0),
                          "The run fails (exit 3) if the crack has not run by this traction. Unit: Pa. Range: > 0.");
        prm.declare_entry("Bisection tolerance", "2e-3", Patterns::Double(0),
                          "The critical load is bracketed to this relative width. Unit: 1. Range: > 0.");
        prm.declare_entry("Runaway length", "1e-3", Patterns::Double(0),
                          "A crack whose tip (d >= 0.95) passes this far beyond the notch has run. Unit: m. Range: > 0.");
        prm.leave_subsection();
      }

      void
      parse(ParameterHandler &prm, const ParameterScope &scope)
      {
        prm.enter_subsection("Fracture specimen");
        width        = prm.get_double("Width");
        height       = prm.get_double("Height");
        notch        = prm.get_double("Notch length");
        cells_across = prm.get_integer("Coarse cells across");
        refinements  = prm.get_integer("Path refinements");
        band         = prm.get_double("Path half-width");
        material.youngs_modulus = prm.get_double("Young's modulus");
        material.poissons_ratio = prm.get_double("Poisson's ratio");
        material.toughness      = prm.get_double("Fracture toughness");
        material.length         = prm.get_double("Internal length");
        material.tolerance      = prm.get_double("Staggered tolerance");
        material.max_iterations = prm.get_integer("Staggered iterations");
        load_increment          = prm.get_double("Load increment");
        maximum_load            = prm.get_double("Maximum load");
        bisection               = prm.get_double("Bisection tolerance");
        runaway                 = prm.get_double("Runaway length");
        prm.leave_subsection();
        for (const auto &[key, value] : {std::pair{"Width", width}, {"Height", height}, {"Notch length", notch},
                                         {"Path half-width", band}, {"Young's modulus", material.youngs_modulus},
                                         {"Fracture toughness", material.toughness},
                                         {"Internal length", material.length},
                                         {"Staggered tolerance", material.tolerance},
                                         {"Load increment", load_increment}, {"Maximum load", maximum_load},
                                         {"Bisection tolerance", bisection}, {"Runaway length", runaway}})
          scope.require(value > 0, key, "must be > 0");
        const double cell = width / cells_across;
        const auto   whole = [&](const double x) { return std::abs(x / cell - std::round(x / cell)) < 1e-9; };
        scope.require(height >= width, "Height", "must be >= Width (the reference is the long strip's)");
        scope.require(notch <= 0.6 * width, "Notch length", "must be <= 0.6 Width (the reference's range)");
        scope.require(whole(notch) && whole(height / 2), "Notch length",
                      "Notch length and Height / 2 must be whole numbers of coarse cells (Width / Coarse cells "
                      "across = " + std::to_string(cell) + " m)");
        scope.require(runaway < width - notch, "Runaway length", "must be shorter than the ligament, Width - Notch length");
        scope.require(bisection >= 1e-6, "Bisection tolerance", "must be >= 1e-6 (a double's bisection stalls below)");
        scope.require(maximum_load <= 1000 * load_increment, "Load increment",
                      "at most 1000 increments up to Maximum load");
        // bounded sizes: the coarse grid, and the refined band's cells estimated
        const double coarse_cells = cells_across * (height / cell);
        const double fine         = cell / std::pow(2.0, refinements);
        const double band_cells   = (width / fine) * (2 * band / fine + 4 * refinements);
        scope.require(coarse_cells <= 1e6, "Height", "at most 1e6 coarse cells (Coarse cells across x Height / Width)");
        scope.require(coarse_cells + band_cells <= 4e6, "Path refinements",
                      "the refined band would hold about " + std::to_string(static_cast<long>(std::min(band_cells, 1e15))) +
                        " cells; at most 4e6");
      }

      /// F(a/W) of the reference (the file's header).
      double
      shape_factor() const
      {
        const double a = notch / width;
        return 1.12 - 0.231 * a + 10.55 * a * a - 21.72 * a * a * a + 30.39 * a * a * a * a;
      }

      /// The plate with its slit: a grid of square cells whose nodes on the notch (y = 0,
      /// x < a) are doubled, the lower row of cells taking the copies.
      void
      make_mesh(parallel::distributed::Triangulation<2> &tria) const
      {
        const double   cell = width / cells_across;
        const unsigned nx = cells_across, ny = static_cast<unsigned>(std::lround(height / cell));
        const unsigned mid = ny / 2, notch_cells = static_cast<unsigned>(std::lround(notch / cell));
        std::vector<Point<2>> vertices;
        const auto            index = [&](unsigned i, unsigned j) { return j * (nx + 1) + i; };
        for (unsigned j = 0; j <= ny; ++j)
          for (unsigned i = 0; i <= nx; ++i)
            vertices.emplace_back(i * cell, j * cell - height / 2);
        std::vector<unsigned> copy(notch_cells, 0); // the notch's lower faces' vertices
        for (unsigned i = 0; i < notch_cells; ++i)
          {
            copy[i] = vertices.size();
            vertices.push_back(vertices[index(i, mid)]);
          }
        std::vector<CellData<2>> cells;
        for (unsigned j = 0; j < ny; ++j)
          for (unsigned i = 0; i < nx; ++i)
            {
              CellData<2> c;
              c.vertices = {index(i, j), index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)};
              if (j + 1 == mid)
                for (unsigned k : {2u, 3u})
                  if (i + k - 2 < notch_cells)
                    c.vertices[k] = copy[i + k - 2];
              cells.push_back(c);
            }
        tria.create_triangulation(vertices, cells, SubCellData());
        for (const auto &cell_it : tria.active_cell_iterators())
          for (const auto &face : cell_it->face_iterators())
            if (face->at_boundary())
              {
                const Point<2> c = face->center();
                face->set_boundary_id(std::abs(c[0]) < 1e-9 * width           ? left
                                      : std::abs(c[0] - width) < 1e-9 * width ? right
                                      : c[1] < -height / 2 * (1 - 1e-9)      ? bottom
                                      : c[1] > height / 2 * (1 - 1e-9)       ? top
                                                                              : notch_faces);
              }
        for (unsigned r = 0; r < refinements; ++r)
          {
            for (const auto &cell_it : tria.active_cell_iterators())
              if (cell_it->is_locally_owned() && std::abs(cell_it->center()[1]) < band + cell_it->diameter())
                cell_it->set_refine_flag();
            tria.execute_coarsening_and_refinement();
          }
      }
    };

    class FractureSpecimen : public Scenario
    {
    public:
      FractureSpecimen(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.scope("Needle").require(!scene.needle.present(), "Shape", "a fracture specimen has no needle");
        scene.scope("Closure").require(!scene.closure.present(), "Gap probes", "a fracture specimen has no wound");
        specimen.parse(prm, scene.scope("Fracture specimen"));
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          MPI_Comm                                comm = MPI_COMM_WORLD;
          parallel::distributed::Triangulation<2> tria(comm);
          {
            TimerOutput::Scope section(timer, "mesh");
            specimen.make_mesh(tria);
          }
          using Model = tearing::PhaseFieldFracture<2>;
          Model::Loading loading;
          Tensor<1, 2> up;
          up[1]                     = 1;
          loading.tractions[top]    = up;
          loading.tractions[bottom] = -up;
          // self-equilibrated load: the pins hold rigid motions without a reaction
          loading.pins = {{Point<2>(specimen.width, 0), ComponentMask(std::vector<bool>{true, true})},
                          {Point<2>(specimen.width, specimen.height / 2), ComponentMask(std::vector<bool>{true, false})}};
          const double a = specimen.notch;
          // the notch is a crack: d = 1 on its faces and tip, so that the tip carries
          // the crack's damage profile from the first load; from a bare slit the tip
          // must first grow that profile, which takes 23 % more load here (docs/tearing.md)
          loading.cracked = [&](const Point<2> &p) { return std::abs(p[1]) < 1e-12 && p[0] <= a * (1 + 1e-12); };
          Model model(comm, specimen.material, tria, loading);

          const auto   tip = [&] {
            return model.damage_extent([](const Point<2> &p) { return std::abs(p[1]) < 1e-12 ? p[0] : -1.0; }, 0.95);
          };
          const double h = model.smallest_cell_size(
            [&](const Point<2> &p) { return std::abs(p[1]) < specimen.band && p[0] > a; });
          const double e_prime = specimen.material.youngs_modulus /
                                 (1 - specimen.material.poissons_ratio * specimen.material.poissons_ratio);
          const double g_eff     = model.effective_toughness(h);
          const double reference = std::sqrt(e_prime * g_eff / (M_PI * a)) / specimen.shape_factor();

          RunSummary summary(recorder.summary());
          summary.begin(scene);
          auto &mesh    = recorder.summary()["mesh"];
          mesh["cells"] = tria.n_global_active_cells();
          mesh["dofs"]  = model.n_dofs();
          mesh["h"]     = h;
          pcout << "suturesim: scene '" << scene.name << "', single-edge-notched tension, "
                << tria.n_global_active_cells() << " cells, " << model.n_dofs() << " DoFs, h = " << h
                << " m, l/h = " << specimen.material.length / h << ", a/l = " << a / specimen.material.length
                << "; LEFM critical traction " << reference << " Pa\n";

          recorder.set_columns({"traction [Pa]", "crack tip [m]", "left edge stretch [m]", "elastic energy [J/m]",
                                "fracture energy [J/m]", "staggered iterations [1]", "stable [1]"});
          unsigned   index = 0;
          const auto record = [&](const double load, const Model::Step &step, const bool stable) {
            const double stretch = model.displacement_at(Point<2>(0, specimen.height / 2))[1] -
                                   model.displacement_at(Point<2>(0, -specimen.height / 2))[1];
            recorder.add_row({load, std::max(tip(), a), stretch, model.elastic_energy(), model.fracture_energy(),
                              static_cast<double>(step.iterations), stable ? 1.0 : 0.0});
            std::ostringstream name;
            name << "specimen_" << std::setw(5) << std::setfill('0') << index << ".vtu";
            model.write_vtu((std::filesystem::path(recorder.directory()) / name.str()).string(), load, index);
            recorder.add_vtu("specimen", index, name.str());
            ++index;
          };
          // a trial from the last stable state: stable if it converged with the tip near the notch
          const auto trial = [&](const double load) {
            model.restore();
            TimerOutput::Scope section(timer, "alternate minimisation");
            const auto step   = model.solve(load, [&] { return tip() > a + specimen.runaway; });
            const bool stable = step.converged && tip() <= a + specimen.runaway;
            return std::pair{step, stable};
          };

          double stable_load = 0, runaway_load = 0;
          unsigned trials = 0;
          for (double load = specimen.load_increment; runaway_load == 0; load += specimen.load_increment)
            {
              if (load > specimen.maximum_load * (1 + 1e-12))
                throw SolverError("the crack has not run at Fracture specimen/Maximum load = " +
                                  std::to_string(specimen.maximum_load) + " Pa");
              const auto [step, stable] = trial(load);
              ++trials;
              record(load, step, stable);
              if (stable)
                {
                  model.accept();
                  stable_load = load;
                }
              else
                runaway_load = load;
            }
          while (runaway_load - stable_load > specimen.bisection * runaway_load)
            {
              const double load          = 0.5 * (stable_load + runaway_load);
              const auto [step, stable]  = trial(load);
              ++trials;
              if (stable)
                {
                  model.accept();
                  stable_load = load;
                }
              else
                runaway_load = load;
              pcout << "  traction " << load << " Pa: " << (stable ? "stable" : "runs") << " ("
                    << step.iterations << " iterations)\n";
            }
          // the crack at the last runaway load, for the picture of its path
          const auto [step, stable] = trial(runaway_load);
          record(runaway_load, step, stable);

          const double critical = 0.5 * (stable_load + runaway_load);
          auto        &metrics  = recorder.summary()["metrics"]["fracture"];
          metrics["critical_traction"]       = critical;
          metrics["critical_traction_range"] = {stable_load, runaway_load};
          metrics["lefm_critical_traction"]  = reference;
          metrics["relative_error"]          = critical / reference - 1;
          metrics["effective_toughness"]     = g_eff;
          metrics["shape_factor"]            = specimen.shape_factor();
          metrics["cell_size_on_path"]       = h;
          metrics["notch_over_length"]       = a / specimen.material.length;
          metrics["trials"]                  = trials;
          pcout << "  critical traction " << critical << " Pa (" << stable_load << " - " << runaway_load
                << "), LEFM " << reference << " Pa: " << std::showpos << 100 * (critical / reference - 1)
                << std::noshowpos << " %\n";
        });
      }

    private:
      SceneParameters &scene;
      Specimen         specimen;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"fracture specimen",
       "a notched plate broken by AT1 phase-field fracture, its critical load against LEFM (Model = accurate, Bodies "
       "= fracture specimen)",
       Specimen::declare,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "fracture specimen"; },
       [](ParameterHandler &prm, SceneParameters &s) {
         return std::unique_ptr<Scenario>(new FractureSpecimen(prm, s));
       }});
  } // namespace
} // namespace suturesim::scene
