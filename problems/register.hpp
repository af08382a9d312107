/// The entry point of the built-in problems (the list is in problems/register_all.cpp).
#pragma once
#include "problems/problem.hpp"

namespace mfv {

/// Registers every built-in problem (the list: problems/register_all.cpp).
void register_all_problems(ProblemRegistry& r);

}  // namespace mfv
