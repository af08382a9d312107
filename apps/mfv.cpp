/// mfv: meshfree verification suite command line (CLI11).
#include <iostream>

#include <CLI/CLI.hpp>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"

int main(int argc, char** argv) {
  CLI::App app{"mfv: verification suite for meshfree particle methods"};
  app.require_subcommand(1);

  auto* list = app.add_subcommand("list", "name every kernel, approximation, method and problem "
                                          "with its parameters");

  mfv::RunOptions run;
  auto* cmd_run = app.add_subcommand("run", "run one case and print its errors");
  cmd_run->add_option("problem", run.problem, "problem name (see mfv list)")->required();
  cmd_run->add_option("--method,-m", run.method, "method name")->required();
  cmd_run->add_option("--params,-p", run.method_params, "method parameters key=value,...");
  cmd_run->add_option("--problem-params", run.problem_params, "problem parameters key=value,...");
  cmd_run->add_option("--nodes,-n", run.nodes, "number of particles")->required();
  cmd_run->add_option("--perturb", run.perturbation, "random particle offsets, fraction of dx");

  CLI11_PARSE(app, argc, argv);
  try {
    const mfv::Catalogue catalogue;
    if (*list) mfv::command_list(catalogue, std::cout);
    if (*cmd_run) mfv::command_run(catalogue, run, std::cout);
  } catch (const mfv::InputError& e) {
    std::cerr << "mfv: input error: " << e.what() << "\n";
    return 2;
  } catch (const mfv::SingularError& e) {
    std::cerr << "mfv: singular: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "mfv: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
