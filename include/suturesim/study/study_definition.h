#pragma once
/**
 * @file
 * A study file (issue 24): a deal.II .prm, checked like a scene (file:line errors), that
 * names a base scene, the settings of a reference case, the settings every case shares,
 * and the cases — the product of axes over any scene parameter by its path, and/or a
 * list. Each case is the base scene with its settings applied as `--set` would apply
 * them, so it is an ordinary suturesim run, reproducible by itself.
 *
 *   set Name       = patch_load_pareto
 *   set Base scene = ../../benchmarks/block_patch_load/block_patch_load.prm
 *   subsection Reference
 *     set Settings = Model=accurate
 *   end
 *   subsection Cases
 *     set Settings = Model=realtime
 *     set Axes     = Realtime/Integrator = xpbd | quasi-static; Realtime/xpbd/Iterations = 1 | 4
 *     set List     = few: Realtime/xpbd/Iterations=2, Time/Step size=0.002
 *   end
 *
 * Settings are "Path/Key=value" separated by ",", axes "Path/Key = v1 | v2 | …"
 * separated by ";", listed cases "name: settings" separated by ";". Axis cases are
 * named by their values (characters other than letters, digits, '.', '-' become '_'),
 * joined by "_".
 */

#include <string>
#include <vector>

namespace suturesim::study
{
  struct Case
  {
    std::string              name;
    std::vector<std::string> settings; ///< "Path/Key=value", applied in order
  };

  struct StudyDefinition
  {
    std::string       name;
    std::string       file;       ///< the study file, for messages
    std::string       base_scene; ///< resolved against the study file's folder
    Case              reference;  ///< named "reference"
    std::vector<Case> cases;      ///< the product of the axes, then the listed ones

    /// Reads and checks @p study_file: every case's settings are applied to the base
    /// scene as the run would apply them, so an unknown path or a bad value is found
    /// now; errors are InputErrors "study_file:line: key: problem".
    static StudyDefinition
    read(const std::string &study_file);
  };
} // namespace suturesim::study
