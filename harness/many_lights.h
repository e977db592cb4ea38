// Many local lights (Kämpe 2015 §4, §5.3, Fig. 3): a scene lit by hundreds of bounded spot
// lights, one precomputed structure per light, the distribution of their sizes and build times,
// and the shadows of every light evaluated for a camera view with Tiled Shading light lists
// (Olsson & Assarsson 2011) and 9×9 PCF. Each part has its own file under many_lights/; the
// command is harness/cli/many_lights_command.h.
#pragma once

#include "harness/cli/many_lights_command.h"
#include "harness/many_lights/builds.h"
#include "harness/many_lights/light_lists.h"
#include "harness/many_lights/placement.h"
#include "harness/many_lights/statistics.h"
#include "harness/many_lights/view_evaluation.h"
