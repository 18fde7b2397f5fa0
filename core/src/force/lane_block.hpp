// SPDX-License-Identifier: MIT
//
// A block of pairs through the lanes (docs/plugin-abi.md, "Lanes"): up to kBlock pairs that are
// contacts in the lanes of one rule, or pairs apart, in three passes over the block: the
// geometry of every pair, with the contacts' inputs into the rule's LaneBatch; one call of the
// lane law for them all (a contact it declines goes through FDlaw); the finish of every pair in
// pair order, as runPair does it. Not installed.
#pragma once

#include <cstddef>
#include <string>

#include "force/pair.hpp"

namespace talus {

/// Stops before a wall pair, a contact outside the lanes or of another rule, and a pair that
/// touches for the first time. Returns the first pair after the block: i when the pair at i is
/// none of these. `at` follows the pair being finished (the threads' failure point).
template <class Features, Delivery kMode>
std::size_t runLaneBlock(const ForceView& v, ForceSums& sums, std::size_t i, std::size_t end,
                         LaneScratch& ls, ForceThreadPart* part, std::string& error,
                         LaneCounts& counts, std::size_t& at) {
    LaneTable* table = nullptr;
    std::size_t row_bytes = 0;
    int n = 0, nb = 0;
    for (std::size_t j = i; j < end && n < LaneScratch::kBlock; ++j) {
        const Pair& p = v.pairs[j];
        if (p.wall) break;
        if (p.active) {
            if (p.lane == kNoLane || v.rule(p).lane_mode != LaneMode::Blocks ||
                (table && v.rule(p).lanes.get() != table))
                break;
            if (!table) {
                table = v.rule(p).lanes.get();
                row_bytes = sizeof(double) * std::size_t(table->law().state_size);
            }
        }
        PairEntry& e = ls.entry[n];
        const PairStep step = geometryPass<Features>(v, j, e, nullptr);
        if (step == PairStep::Touch) break;
        ls.step[n] = step;
        if (step == PairStep::Contact) {
            // (its row is wanted by the law after the block's geometry: ask for it now)
            const char* row = reinterpret_cast<const char*>(table->row(p.lane));
            for (std::size_t at_byte = 0; at_byte < row_bytes; at_byte += 64)
                __builtin_prefetch(row + at_byte, 1);
            ls.slot[n] = nb;
            ls.row[nb] = p.lane;
            ls.u_n[nb] = e.g.overlap;
            ls.u_dot_n[nb] = e.u_dot_n;
            ls.u_dot_s[nb] = e.u_dot_s;
            ls.t_dot_rel[nb] = e.t_dot_rel;
            ls.mass_eff[nb] = v.cold[j].mass_eff;
            ls.inv_mass_eff_s[nb] = v.cold[j].inv_mass_eff_s;
            ls.n_force[nb] = p.n_force;
            ls.s_force[nb] = p.s_force;
            ls.moment[nb] = p.moment;
            ++nb;
        }
        ++n;
    }
    if (nb > 0) {
        LaneBatch& batch = ls.batch;
        batch.flags = v.fd_template.flags;
        batch.count = nb;
        batch.tdel = v.dt;
        batch.time = v.fd_template.time;
        batch.state = table->state();
        table->law().law(batch);
        counts.steps += nb;
        // Declined: the object up to date, FDlaw, and back into its row if the model takes it
        // (the row is freed serially when threads run).
        for (int q = 0; q < n; ++q) {
            if (ls.step[q] != PairStep::Contact) continue;
            const int k = ls.slot[q];
            if (!(ls.flags_out[k] & kFdLaneDeclined)) continue;
            ++counts.declined;
            const std::size_t j = i + static_cast<std::size_t>(q);
            Pair& p = v.pairs[j];
            ContactModel* model = v.pairs[j].model;
            table->law().unpack(model, table->row(p.lane));
            FdBlock& fd = ls.declined[static_cast<std::size_t>(k)];
            fd = v.fd_template;
            const PairEntry& e = ls.entry[q];
            fillFd<Features>(v, j, e.g.overlap, e.u_dot_n, e.u_dot_s, e.t_dot_rel, fd);
            lawPass(v, j, fd, error, counts.batched);
            if (table->law().pack(model, table->row(p.lane)) == 0) {
                if constexpr (kMode == Delivery::Parallel)
                    part->lane_releases.emplace_back(table, p.lane);
                else
                    table->release(p.lane);
                p.lane = kNoLane;
            }
        }
    }
    for (int q = 0; q < n; ++q) {
        const std::size_t j = i + static_cast<std::size_t>(q);
        at = j;
        if (ls.step[q] != PairStep::Contact) {
            finishApart<Features, kMode>(v, j, ls.step[q], part);
            continue;
        }
        const int k = ls.slot[q];
        if (ls.flags_out[k] & kFdLaneDeclined) {
            finishContact<Features, kMode>(v, sums, j, ls.entry[q],
                                           ls.declined[static_cast<std::size_t>(k)], false, part);
        } else {
            const LaneResult r = ls.result(k, v.dt);
            finishContact<Features, kMode>(v, sums, j, ls.entry[q], r, false, part);
        }
    }
    return i + static_cast<std::size_t>(n);
}

}  // namespace talus
