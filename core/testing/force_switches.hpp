// SPDX-License-Identifier: MIT
//
// Switches of the force loop for the test suite and the benchmarks, which compare the engine's
// ways of running a law and of delivering forces and prove that they give the same bits. Not
// part of the facade (talus/model.hpp) and not installed: a script or a plugin never needs them.
#pragma once

#include <cstddef>

#include "talus/model.hpp"

namespace talus::testing {

/// Runs the laws of the shipped models that name one (`linear`, `cbond`) inside the force loop
/// on host-owned rows of their state (docs/plugin-abi.md, "Kernels"; default on), or off, their
/// FDlaw. The same bits either way. Off takes every contact off its row at once.
void setKernels(Model& model, bool on);
bool kernels(const Model& model);

/// Threads the force loop would use for `npairs` pairs this step (Model::setThreads, the grain,
/// the models' thread safety).
int forceThreads(const Model& model, std::size_t npairs);

}  // namespace talus::testing
