// SPDX-License-Identifier: MIT
//
// Stopping a run from outside (Ctrl-C). A signal handler may only touch lock-free atomics, so
// the request is one process-wide flag: the CLI's SIGINT handler sets it, and Model::cycle /
// solveTime test it after every step (core/src/step/step.cpp, runSteps). A run that sees it stops
// at the end of the step it is in, so the model is in a consistent state (every phase of the
// step has run), and throws talus::Interrupted (errors.hpp). The flag stays set: a later run
// call stops at once, before its first step, so a script cannot keep cycling after Ctrl-C.
#pragma once

namespace talus {

/// Asks every running cycle/solve to stop at the end of its current step. Async-signal-safe.
void requestStop() noexcept;
/// True once requestStop() was called (until clearStopRequest()).
bool stopRequested() noexcept;
/// Forgets the request (tests; a caller that has handled it and wants to run on).
void clearStopRequest() noexcept;

}  // namespace talus
