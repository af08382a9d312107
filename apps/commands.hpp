/// The `mfv` subcommands, callable from main and from tests.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "verify/catalogue.hpp"

namespace mfv {

/// `mfv list`: every kernel, approximation, integration scheme, method and problem with its
/// parameters.
void command_list(const Catalogue& c, std::ostream& out);

struct RunOptions {
  std::string problem, method, method_params, problem_params;
  int nodes = 0;
  double perturbation = 0;
  std::string vtk;  ///< optional .vtp path
};
/// `mfv run`: one case; prints errors, headline quantity and CPU times.
void command_run(const Catalogue& c, const RunOptions& o, std::ostream& out);

}  // namespace mfv
