#pragma once
/**
 * @file
 * `suturesim calibrate <calibration.prm> [--output DIR] [--jobs N] [--set S/K=V]...`
 * (issue 28, docs/calibration.md). A calibration file is a study file
 * (study/study_definition.h) with a `subsection Calibration`: the scene parameters to
 * fit, each with its initial value and bounds, the weights w_m of the study's error
 * columns e_m, and held-out validation cases. The command checks it as a study (file:line
 * errors, every bound and validation case applied to the base scene), writes the plan
 * (DIR/calibration_plan.json), and hands the fit to postprocess/calibrate.py under
 * Debian's python3: SciPy's bounded trust-region least squares (`least_squares`,
 * method "trf") on the residuals whose squares sum to Σ_m w_m e_m², each evaluation a
 * batch of cases run by `suturesim study --case-list` against the study's one
 * reference (run once and reused). It writes DIR/calibrated.prm (the fitted values as a
 * scene fragment), DIR/calibration.json (values, standard errors, sensitivities, train
 * and validation errors per metric, the objective history) and the history's figure.
 */

#include <string>
#include <vector>

namespace suturesim::study
{
  /// Exit codes: 0 fitted, 2 bad input (one line naming the file and line), 3 the
  /// optimiser stopped without convergence (the best values found are written), 1 the
  /// driver failed otherwise.
  int
  calibrate_command(const std::vector<std::string> &arguments);
} // namespace suturesim::study
