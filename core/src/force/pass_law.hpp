// SPDX-License-Identifier: MIT
//
// Pass 2 of the force loop: a contact's force-displacement law, the model's batched FDlaw with
// a count of one (docs/plugin-abi.md, "Batched FDlaw": no virtual call, the same bits as
// FDlaw) or FDlaw through the vtable. Not installed.
#pragma once

#include <cstdint>
#include <exception>
#include <string>

#include "force/view.hpp"

namespace talus {

/// The law of one contact through the vtable (a model without a batched law, or a rare pair).
/// A model without the SDK's barrier may throw (docs/plugin-abi.md, "Exceptions"): caught here,
/// its text kept in `error` (the thread's own).
inline void callLaw(ContactModel* model, FdBlock& fd, std::string& error) {
    try {
        model->FDlaw(fd);
    } catch (const std::exception& ex) {
        fd.status = 1;
        error = ex.what();
        fd.error = error.c_str();
    } catch (...) {
        fd.status = 1;
        fd.error = "unknown exception";
    }
}

__attribute__((always_inline)) inline void lawPass(const ForceView& v, std::size_t i, FdBlock& fd,
                                                   std::string& error, int64_t& batched_count) {
    const BatchFdLawFn batch = v.batched ? v.rule(v.pairs[i]).batch : nullptr;
    ContactModel* model = v.pairs[i].model;
    if (batch) {
        batch(&model, &fd, 1);
        ++batched_count;
    } else {
        callLaw(model, fd, error);
    }
}

}  // namespace talus
