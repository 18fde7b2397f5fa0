// SPDX-License-Identifier: MIT
//
// Kernels: the host runs a shipped model's law itself, inline in its force loop, when the model
// says which SDK law it runs (talus_plugin_kernel, ABI 1.3; docs/plugin-abi.md, "Kernels") and
// keeps its state in that law's lane rows. The law is compiled here from the same SDK header the
// plugin was compiled from, on the same rows, so a contact gets the same bits as through FDlaw;
// what the kernel declines (a separation, a first touch, a changed mass) goes through FDlaw.
// User models keep the ABI path (FDlaw, the batched law, lane blocks). Not installed.
#pragma once

#include <cstring>

#include "force/scratch.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/sdk/contact_bond_law.hpp"
#include "talus/sdk/lanes.hpp"
#include "talus/sdk/linear_law.hpp"
#include "world/types.hpp"

namespace talus {

/// The kernel of a model: the SDK law it names, if this host has it and the model's lane rows are
/// that law's (their size and the names of their doubles).
inline Kernel kernelOf(const ModelFactory& f) {
    if (f.kernel.empty() || !f.lanes) return Kernel::None;
    const LaneLaw& lanes = *f.lanes;
    auto rowsAre = [&](int size, const char* const* names) {
        if (lanes.state_size != size || !lanes.state_names) return false;
        for (int k = 0; k < size; ++k)
            if (!lanes.state_names[k] || std::strcmp(lanes.state_names[k], names[k]) != 0)
                return false;
        return true;
    };
    if (f.kernel == sdk::LinearLaw::kKernelId &&
        rowsAre(sdk::LinearLaw::kLinearLaneStateSize, sdk::LinearLaw::linearLaneStateNames()))
        return Kernel::Linear;
    if (f.kernel == sdk::ContactBondLaw::kKernelId &&
        rowsAre(sdk::ContactBondLaw::kLaneStateSize, sdk::ContactBondLaw::laneStateNames()))
        return Kernel::ContactBond;
    return Kernel::None;
}

/// A contact's law for a kernel: what FDlaw reads and writes, under FdBlock's names, with the
/// fields a kernel never sets (it declines a step that would fail or break a bond).
struct KernelFd : sdk::LaneFd {
    static constexpr int32_t status = 0;
    static constexpr const char* error = nullptr;
    static constexpr int32_t break_mode = kBreakNone;
    static constexpr double reserved[3] = {0.0, 0.0, 0.0};
};

/// One contact's step by kernel `k` on its row; false: declined (row untouched). The effective
/// masses are read from the contact's cold record only where the law uses them: a kernel's
/// contact otherwise leaves that record alone, which at 50 000 disks is a cache line per contact
/// and step. The linear law solves its shear dashpot with inv_mass_eff_s (only with one, cs > 0)
/// and checks its row's mass_eff against the pair's (declining the step when the mass changed); a
/// mass change takes the contact out of its lane (refreshPairMasses), so the row's mass is the
/// pair's whenever the kernel runs. The contact bond's step uses neither. (`cold` a pointer: a
/// reference may be read ahead of the test, and that read is the one to avoid.)
__attribute__((always_inline)) inline bool runKernel(Kernel k, double* row, const PairCold* cold,
                                                     KernelFd& fd) {
    switch (k) {
        case Kernel::Linear:
            fd.mass_eff = row[sdk::LinearLaw::kLaneMassEff];
            fd.inv_mass_eff_s = row[sdk::LinearLaw::kLaneCs] > 0.0 ? cold->inv_mass_eff_s : 0.0;
            return sdk::LinearLaw::linearLaneStep(row, fd);
        case Kernel::ContactBond:
            return sdk::ContactBondLaw::laneStep(row, fd);
        case Kernel::None:
            break;
    }
    return false;
}

}  // namespace talus
