#include <suturesim/core/error.h>
#include <suturesim/tissue/boundary_conditions.h>

#include <deal.II/base/utilities.h>
#include <deal.II/lac/vector.h>

#include <iostream>
#include <sstream>

namespace suturesim::tissue
{
  using namespace dealii;

  namespace
  {
    const char *list_help = " Comma-separated gmsh physical-group names or boundary ids, "
                            "each optionally followed by ':' and the constrained "
                            "components (x, y, z, or combinations such as xz); all three "
                            "by default. Unit: none.";

    /// Declares a vector-valued muParser function of x, y, z (m) and t (s).
    void
    declare_function(ParameterHandler &prm, const std::string &name)
    {
      prm.enter_subsection(name);
      Functions::ParsedFunction<3>::declare_parameters(prm, 3);
      prm.leave_subsection();
    }

    std::unique_ptr<Functions::ParsedFunction<3>>
    parse_function(ParameterHandler          &prm,
                   const std::string         &name,
                   const ParameterScope &scope)
    {
      prm.enter_subsection(name);
      auto f = std::make_unique<Functions::ParsedFunction<3>>(3);
      try
        {
          f->parse_parameters(prm);
          prm.leave_subsection();
          // muParser compiles on first use: evaluate once so that a bad expression is
          // reported now, with its line, rather than in the middle of a run. deal.II
          // prints muParser's own multi-line diagnosis to std::cerr first; the user gets
          // our one line instead.
          std::ostringstream muted;
          std::streambuf    *cerr_buffer = std::cerr.rdbuf(muted.rdbuf());
          try
            {
              Vector<double> v(3);
              f->vector_value(Point<3>(), v);
            }
          catch (...)
            {
              std::cerr.rdbuf(cerr_buffer);
              throw;
            }
          std::cerr.rdbuf(cerr_buffer);
        }
      catch (const ExceptionBase &e)
        {
          std::ostringstream s;
          e.print_info(s);
          scope.subsection(name).fail("Function expression", one_line(s.str()));
        }
      return f;
    }
  } // namespace

  void
  BoundaryConditions::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Fixed",
                      "",
                      Patterns::List(Patterns::Anything()),
                      std::string("Boundaries held at u = 0.") + list_help);
    prm.declare_entry("Prescribed displacement",
                      "",
                      Patterns::List(Patterns::Anything()),
                      std::string("Boundaries moved by the 'Prescribed displacement "
                                  "function' u = g(x, y, z, t) (x, y, z reference "
                                  "coordinates in m, t in s; result in m).") +
                        list_help);
    prm.declare_entry("Traction",
                      "",
                      Patterns::List(Patterns::Anything()),
                      "Boundaries loaded by the 'Traction function': force per reference "
                      "area t0(x, y, z, t) in Pa. Comma-separated names or ids. Unit: none.");
    prm.declare_entry("Gravity",
                      "0, 0, 0",
                      Patterns::List(Patterns::Double(), 3, 3),
                      "Gravitational acceleration; body force = density * gravity. Unit: "
                      "m/s^2.");
    declare_function(prm, "Prescribed displacement function");
    declare_function(prm, "Traction function");
  }

  void
  BoundaryConditions::parse(ParameterHandler &prm, const ParameterScope &s)
  {
    scope = std::make_unique<ParameterScope>(s);
    dirichlet_specs.clear();
    for (const auto &item : Utilities::split_string_list(prm.get("Fixed")))
      dirichlet_specs.emplace_back(item, false);
    for (const auto &item : Utilities::split_string_list(prm.get("Prescribed displacement")))
      dirichlet_specs.emplace_back(item, true);
    traction_specs = Utilities::split_string_list(prm.get("Traction"));
    const auto g   = Utilities::string_to_double(Utilities::split_string_list(prm.get("Gravity")));
    gravity        = Tensor<1, 3>({g[0], g[1], g[2]});
    displacement_function = parse_function(prm, "Prescribed displacement function", s);
    traction_function     = parse_function(prm, "Traction function", s);
  }

  void
  BoundaryConditions::resolve(const mesh::MeshInfo &mesh)
  {
    dirichlet.clear();
    for (const auto &[spec, prescribed] : dirichlet_specs)
      {
        const std::string key  = prescribed ? "Prescribed displacement" : "Fixed";
        const auto        colon = spec.find(':');
        const std::string name  = Utilities::trim(spec.substr(0, colon));
        std::array<bool, 3> components{{true, true, true}};
        if (colon != std::string::npos)
          {
            const std::string comps = Utilities::trim(spec.substr(colon + 1));
            components              = {{false, false, false}};
            for (const char c : comps)
              {
                if (c < 'x' || c > 'z')
                  scope->fail(key, "component '" + std::string(1, c) + "' in '" + spec +
                                     "' is not x, y or z");
                components[c - 'x'] = true;
              }
            if (comps.empty())
              scope->fail(key, "no components after ':' in '" + spec + "'");
          }
        const auto id = mesh.boundary_id(name, *scope, key);
        for (const auto &other : dirichlet)
          if (other.id == id)
            scope->fail(key, "boundary '" + name + "' is listed twice");
        dirichlet.push_back({id, mesh.boundary_name(id), components, prescribed});
      }
    traction_boundaries.clear();
    for (const auto &name : traction_specs)
      {
        const auto id = mesh.boundary_id(name, *scope, "Traction");
        for (const auto &d : dirichlet)
          if (d.id == id && d.components == std::array<bool, 3>{{true, true, true}})
            scope->fail("Traction", "boundary '" + name + "' is fully constrained already");
        traction_boundaries.insert(id);
      }
  }

  Function<3> &
  BoundaryConditions::displacement(const double t) const
  {
    displacement_function->set_time(t);
    return *displacement_function;
  }

  Function<3> &
  BoundaryConditions::traction(const double t) const
  {
    traction_function->set_time(t);
    return *traction_function;
  }
} // namespace suturesim::tissue
