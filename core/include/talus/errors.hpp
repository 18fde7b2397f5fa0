// SPDX-License-Identifier: MIT
// User-facing errors (tier 2 of docs/architecture.md "Errors"): each says what was wrong and
// where. The Lua layer turns them into Lua errors carrying the script line.
#pragma once

#include <stdexcept>
#include <string>

namespace talus {

/// Base of every error Talus reports to a user.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Bad input: an unknown property, an out-of-range value, a stale id.
class InputError : public Error {
public:
    using Error::Error;
};

/// A plugin could not be loaded or a model failed at the boundary.
class PluginError : public Error {
public:
    using Error::Error;
};

/// The run became unphysical: a non-finite state, energy created by a contact.
class NumericalError : public Error {
public:
    using Error::Error;
};

/// The run was stopped from outside (Ctrl-C, run_control.hpp) at the end of a step. The model
/// is consistent and can be saved or inspected. `beforeStart`: the stop was already requested
/// when the run call began, so it took no step at all.
class Interrupted : public Error {
public:
    Interrupted(const std::string& what, bool before_start)
        : Error(what), m_before_start(before_start) {}
    bool beforeStart() const { return m_before_start; }

private:
    bool m_before_start;
};

/// Internal invariant; a bug in Talus, not in the input.
#define TALUS_ASSERT(cond, msg)                                                              \
    do {                                                                                     \
        if (!(cond))                                                                         \
            throw ::talus::Error(std::string("internal error: ") + (msg) + " (" #cond ", " + \
                                 __FILE__ + ":" + std::to_string(__LINE__) + ")");           \
    } while (0)

}  // namespace talus
