/// A command that runs plugins' code is supervised: mfv starts itself again as a child and
/// waits for it, so that a plugin calling _exit() while a case runs (which no handler can
/// catch in-process: _exit(0) made `mfv verify` exit 0 with the case half run, issue 45) ends
/// the command with exit 1 naming the plugins, never with the plugin's status. The child
/// reports its status through a pipe when the command has finished; a child that ends
/// without reporting did not finish. A child killed by a signal is named, and the supervisor
/// dies of the same signal, so a crash still reads as a crash. Not under mpirun (every rank
/// is mpirun's child and must stay so) and not in the child itself.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace mfv {

/// In the child: takes the completion channel out of the environment (so that a solver or
/// another mfv it starts does not inherit it). Call first in main. True when this process
/// is a supervised child.
bool adopt_supervision();

/// In the child, when the plugins are loaded and their hooks have registered what they add
/// (the Catalogue is built): an end before this is the plugins' registration failing (the
/// supervisor ends with 2, as a refused plugin), after it the command's (1).
void report_registered();

/// In the child, when the command has finished with `status`: reports it to the supervisor.
/// Nothing outside a supervised child.
void report_finished(int status);

/// In a process forked from a supervised child that is not the command (a plugin's probe
/// load): forgets the channel, so that only the command reports.
void forget_supervision();

/// In the parent, when `plugins` (their file names, for the message) are about to be
/// loaded and this process is not a supervised child nor under mpirun: runs the same
/// command line (`argv`) in a child and returns the exit code mfv should end with; nullopt
/// when no supervision applies (the caller runs the command itself).
std::optional<int> supervise(char** argv, const std::vector<std::string>& plugins);

}  // namespace mfv
