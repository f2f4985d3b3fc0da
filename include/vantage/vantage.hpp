#pragma once
/// Umbrella header of libvantage: scene -> reference -> candidates -> observe -> select -> report.
#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/problem.hpp"
#include "vantage/reference.hpp"
#include "vantage/report.hpp"
#include "vantage/scene.hpp"
#include "vantage/select.hpp"
#include "vantage/sensors.hpp"
#include "vantage/types.hpp"
