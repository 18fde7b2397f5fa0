// SPDX-License-Identifier: MIT
//
// What the engine says: numbers and vectors for messages, warnings, and the descriptions that
// name a ball or a pair (world/messages.cpp). Not installed.
#pragma once

#include <string>

#include "world/world.hpp"

namespace talus {

/// A number for a message: `digits` significant digits (printf %g).
std::string messageNumber(double v, int digits = 6);
/// "(x, y)" with %g numbers, for messages.
std::string vecText(const Vec2& v);
/// To the model's warning handler (stderr by default).
void warn(World& world, const std::string& text);
/// Stops the run: "non-finite state at step N (t = ...): what".
[[noreturn]] void throwNonFinite(const World& world, const std::string& what);
/// What a severe finding's error adds: why it is severe (`why`), and how to report such findings
/// as warnings instead (docs/physics/guard.md, "Severe findings").
std::string severeNote(const std::string& why);
/// "ball 3 at (x, y) and wall 2 (segment 1)", for messages.
std::string describePair(const World& world, const Pair& p);

}  // namespace talus
