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

/// Internal invariant; a bug in Talus, not in the input.
#define TALUS_ASSERT(cond, msg)                                                              \
    do {                                                                                     \
        if (!(cond))                                                                         \
            throw ::talus::Error(std::string("internal error: ") + (msg) + " (" #cond ", " + \
                                 __FILE__ + ":" + std::to_string(__LINE__) + ")");           \
    } while (0)

}  // namespace talus
