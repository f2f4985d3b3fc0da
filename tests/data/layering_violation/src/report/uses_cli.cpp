// A fixture for the `layering_catches_violations` test: the library may not include the CLI.
#include "commands.hpp"
