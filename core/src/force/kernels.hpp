// SPDX-License-Identifier: MIT
//
// The runner table: the ways the host runs a contact model's law. A law runs one of two ways:
// the model's FDlaw through the ABI (every plugin), or, for a shipped model that names the SDK
// law it runs (talus_plugin_kernel, ABI 1.3; docs/plugin-abi.md, "Kernels"), the host's own
// copy of that law, inline in the force loop, on the contact's row of state in the model's lane
// layout. One row of kKernelTable per such law, as LAMMPS keeps one row per granular sub-model;
// the way is chosen once per rule, when the rule is made (kernelOf: Rule::kernel). The law is
// compiled here from the same SDK header the plugin was compiled from, on the same rows, so a
// contact gets the same bits as through FDlaw; what a kernel declines (a separation, a first
// touch, a changed mass) goes through FDlaw. Not installed.
#pragma once

#include <cstring>

#include "talus/plugin_registry.hpp"
#include "talus/sdk/contact_bond_law.hpp"
#include "talus/sdk/lanes.hpp"
#include "talus/sdk/linear_law.hpp"
#include "world/types.hpp"

namespace talus {

/// One law the host runs itself: the model's kernel id and its rows (size, names of the doubles).
struct KernelRow {
    Kernel kernel;
    const char* id;
    int row_size;
    const char* const* (*row_names)();
};

inline constexpr KernelRow kKernelTable[] = {
    {Kernel::Linear, sdk::LinearLaw::kKernelId, sdk::LinearLaw::kLinearLaneStateSize,
     &sdk::LinearLaw::linearLaneStateNames},
    {Kernel::ContactBond, sdk::ContactBondLaw::kKernelId, sdk::ContactBondLaw::kLaneStateSize,
     &sdk::ContactBondLaw::laneStateNames},
};

/// The kernel of a model: the table's row of the SDK law it names, if its lane rows are that
/// law's (their size and the names of their doubles); else None (FDlaw).
inline Kernel kernelOf(const ModelFactory& f) {
    if (f.kernel.empty() || !f.lanes) return Kernel::None;
    const LaneLaw& lanes = *f.lanes;
    for (const KernelRow& row : kKernelTable) {
        if (f.kernel != row.id || lanes.state_size != row.row_size || !lanes.state_names) continue;
        const char* const* names = row.row_names();
        bool same = true;
        for (int k = 0; k < row.row_size && same; ++k)
            same = lanes.state_names[k] && std::strcmp(lanes.state_names[k], names[k]) == 0;
        if (same) return row.kernel;
    }
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

/// What a force loop is compiled for: the rows of one kernel (every rule in rows this step runs
/// it: no switch per contact), or of any (the kernel looked up per contact).
enum class Runner : uint8_t { Any, Linear, ContactBond };

/// One contact's step by kernel K on its row; false: declined (row untouched). The effective
/// masses are read from the contact's cold record only where the law uses them: a kernel's
/// contact otherwise leaves that record alone, which at 50 000 disks is a cache line per contact
/// and step. The linear law solves its shear dashpot with inv_mass_eff_s (only with one, cs > 0)
/// and checks its row's mass_eff against the pair's (declining the step when the mass changed); a
/// mass change takes the contact out of its row (refreshPairMasses), so the row's mass is the
/// pair's whenever the kernel runs. The contact bond's step uses neither. (`cold` a pointer: a
/// reference may be read ahead of the test, and that read is the one to avoid.)
template <Kernel K>
__attribute__((always_inline)) inline bool kernelStep(double* row, const PairCold* cold,
                                                      KernelFd& fd) {
    if constexpr (K == Kernel::Linear) {
        fd.mass_eff = row[sdk::LinearLaw::kLaneMassEff];
        fd.inv_mass_eff_s = row[sdk::LinearLaw::kLaneCs] > 0.0 ? cold->inv_mass_eff_s : 0.0;
        return sdk::LinearLaw::linearLaneStep(row, fd);
    } else if constexpr (K == Kernel::ContactBond) {
        return sdk::ContactBondLaw::laneStep(row, fd);
    } else {
        return false;
    }
}

/// The kernel a runner is compiled for (None for Runner::Any: per contact).
template <Runner R>
constexpr Kernel kRunnerKernel = R == Runner::Linear        ? Kernel::Linear
                                 : R == Runner::ContactBond ? Kernel::ContactBond
                                                            : Kernel::None;

/// Doubles per row, known at compile time when the runner is one kernel's.
template <Runner R>
inline uint32_t rowSize(uint32_t size_of_rule) {
    if constexpr (R == Runner::Linear) return sdk::LinearLaw::kLinearLaneStateSize;
    if constexpr (R == Runner::ContactBond) return sdk::ContactBondLaw::kLaneStateSize;
    return size_of_rule;
}

/// Contact step by the rule's kernel `k` under runner R: a direct call when R names one kernel,
/// else a switch.
template <Runner R>
__attribute__((always_inline)) inline bool runKernel(Kernel k, double* row, const PairCold* cold,
                                                     KernelFd& fd) {
    if constexpr (R != Runner::Any) {
        (void)k;
        return kernelStep<kRunnerKernel<R>>(row, cold, fd);
    } else {
        switch (k) {
            case Kernel::Linear:
                return kernelStep<Kernel::Linear>(row, cold, fd);
            case Kernel::ContactBond:
                return kernelStep<Kernel::ContactBond>(row, cold, fd);
            case Kernel::None:
                break;
        }
        return false;
    }
}

}  // namespace talus
