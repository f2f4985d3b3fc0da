// A fixture for the `layering_catches_violations` test: selection may not cast rays.
#include <embree3/rtcore.h>

#include "vantage/observe.hpp"
