// SPDX-License-Identifier: MIT
//
// Pass 2 of the force loop: a contact's force-displacement law, one of the two ways of the
// runner table (kernels.hpp): the model's FDlaw through the vtable, or the host's kernel of the
// model's SDK law on the contact's row, which hands a declined step to FDlaw. Not installed.
#pragma once

#include <cstddef>
#include <exception>
#include <string>

#include "force/kernels.hpp"
#include "force/pass_geometry.hpp"
#include "force/view.hpp"

namespace talus {

/// The law of one contact through the vtable. A model without the SDK's barrier may throw
/// (docs/plugin-abi.md, "Exceptions"): caught here, its text kept in `error` (the thread's own).
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

/// A kernel's block from pass 1's result: the law's inputs, its last forces.
inline KernelFd kernelBlock(const ForceView& v, const Pair& p, const PairEntry& e) {
    KernelFd kf;
    fillLawInputs(v, p, e.g.overlap, e.u_dot_n, e.u_dot_s, e.t_dot_rel, kf);
    return kf;
}

/// The law of contact i on its kernel row (runner R), into `kf`; false: the kernel declined, and
/// FDlaw ran on the contact's object (brought up to date from the row) into `fd` instead. A row
/// the model no longer takes after that FDlaw is freed: at once, or by the serial part when
/// threads run (`release`).
template <class Features, Runner R>
__attribute__((always_inline)) inline bool kernelLaw(const ForceView& v, std::size_t i,
                                                     const PairEntry& e, KernelFd& kf, FdBlock& fd,
                                                     ForceThreadPart& part, bool release) {
    Pair& p = v.pairs[i];
    const RuleRows& rr = v.rowsOf(p);
    double* row = rr.base + std::size_t{p.lane} * rowSize<R>(rr.size);
    kf = kernelBlock(v, p, e);
    if constexpr (Features::kEnergy)
        for (double& en : kf.energy) en = 0.0;
    ++part.counts.kernel;
    if (runKernel<R>(rr.kernel, row, &v.cold[i], kf)) return true;
    ++part.counts.kernel_declined;
    LaneTable& table = *v.rule(p).lanes;
    table.law().unpack(p.model, row);
    fd = v.fd_template;
    fillFd<Features>(v, i, e.g.overlap, e.u_dot_n, e.u_dot_s, e.t_dot_rel, fd);
    callLaw(p.model, fd, part.error);
    if (table.law().pack(p.model, row) == 0) {
        if (release)
            table.release(p.lane);
        else
            part.row_releases.emplace_back(&table, p.lane);
        p.lane = kNoLane;
    }
    return false;
}

}  // namespace talus
