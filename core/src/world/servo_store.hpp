// SPDX-License-Identifier: MIT
//
// The servos of a model (talus/servo.hpp): each moves a set of walls to hold a target, set every
// step by step/servo.cpp. Indexed by ServoId::index - 1; a removed servo stays as a dead entry
// (ids are never re-used). Not installed.
#pragma once

#include <vector>

#include "talus/servo.hpp"

namespace talus {

struct ServoData {
    bool alive = true;
    ServoState state;
    /// The speed when the servo was set: a ramp of a rate or velocity starts from it.
    double ramp_from = 0.0;
};

struct ServoStore {
    std::vector<ServoData> list;
    int on = 0;  // live servos switched on: the phase runs only when there is one
};

}  // namespace talus
