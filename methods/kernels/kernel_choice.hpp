/// A plugin's choice of kernel, declared once and forwarded by declaration: the key `kernel`
/// and, for every parameter a registered kernel declares, the key `kernel-<name>`
/// (kernel-dim, kernel-cutoff, kernel-c, and a plugin kernel's own), optional: left unset,
/// the chosen kernel keeps its own default. So `-m efg -p kernel=gaussian,kernel-cutoff=3`
/// reaches the Gaussian through the method and its MLS approximation, and a new kernel's
/// parameters are choices of every method the moment it is registered.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "methods/core/params.hpp"
#include "methods/kernels/register.hpp"

namespace mfv {

/// `kernel` (default `def`, among `choices`, every registered kernel when empty) and the
/// optional `kernel-<name>` of every parameter the registered kernels declare.
ParamSchema kernel_choice(const KernelRegistry& kernels, std::string def, std::string description,
                          std::vector<std::string> choices = {});

/// The kernel `p` chooses, built with its `kernel-<name>` values as its own parameters.
/// InputError when `p` sets a `kernel-<name>` the chosen kernel does not declare, or when the
/// kernel fails a property every method needs (methods/kernels/kernel_admission.hpp).
std::unique_ptr<Kernel> make_kernel(const KernelRegistry& kernels, const Params& p);

/// `child` plus `kernel` and every `kernel-<name>` set in `parent`: what a method hands to an
/// approximation declaring kernel_choice.
Params with_kernel(Params child, const Params& parent);

}  // namespace mfv
