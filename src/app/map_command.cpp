#include "commands.h"
namespace dynamap::app {
int runMap(const Args&) { return kExitError; }
}  // namespace dynamap::app
