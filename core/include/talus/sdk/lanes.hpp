// SPDX-License-Identifier: MIT
//
// Lanes (ABI 1.2; docs/plugin-abi.md, "Lanes"): a model's per-contact state kept in rows the
// host owns, and its law run over many contacts per call (talus::LaneLaw, talus::LaneBatch).
//
// The way to keep the lane law bit for bit equal to FDlaw is to run the same code: write the
// law as a template on its block (FdBlock or LaneFd, which has FdBlock's field names) and run
// it on a copy of the contact's state loaded from its row. A model D offers lanes with
//   static constexpr int kLaneStateSize;                  // doubles of state per contact
//   static const char* const* laneStateNames();           // kLaneStateSize names
//   bool toLane(double* row) const;                       // state -> row; false: not now
//   void fromLane(const double* row);                     // row -> state
//   static bool laneStep(double* row, LaneFd& fd);        // the step; false: declined, and
//                                                         // nothing written to the row
// and exports `talus_plugin_lanes` returning laneLawOf<D>() (plugins/linear/linear.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "talus/contact_model.hpp"

namespace talus::sdk {

/// What FDlaw reads and writes in an FdBlock, for one contact of a lane batch, under the same
/// names.
struct LaneFd {
    uint32_t flags = 0;
    double u_n = 0.0, u_dot_n = 0.0, u_dot_s = 0.0, t_dot_rel = 0.0;
    double tdel = 0.0, du_n = 0.0, du_s = 0.0, dtheta = 0.0;
    double mass_eff = 0.0, inv_mass_eff_s = 0.0, time = 0.0;
    double n_force = 0.0, s_force = 0.0, moment = 0.0;
    double knest = 0.0, ksest = 0.0, krest = 0.0;
    double energy[kEnergyCount];

    /// Contact k's inputs, with the increments computed as the host computes them for FDlaw.
    static LaneFd in(const LaneBatch& b, int32_t k) {
        LaneFd fd;
        fd.flags = b.flags;
        fd.tdel = b.tdel;
        fd.time = b.time;
        fd.u_n = b.u_n[k];
        fd.u_dot_n = b.u_dot_n[k];
        fd.u_dot_s = b.u_dot_s[k];
        fd.t_dot_rel = b.t_dot_rel[k];
        fd.du_n = fd.u_dot_n * fd.tdel;
        fd.du_s = fd.u_dot_s * fd.tdel;
        fd.dtheta = fd.t_dot_rel * fd.tdel;
        fd.mass_eff = b.mass_eff[k];
        fd.inv_mass_eff_s = b.inv_mass_eff_s[k];
        fd.n_force = b.n_force[k];
        fd.s_force = b.s_force[k];
        fd.moment = b.moment[k];
        if (fd.flags & kFdEnergyOn)
            for (double& e : fd.energy) e = 0.0;
        return fd;
    }

    void out(const LaneBatch& b, int32_t k) const {
        b.n_force[k] = n_force;
        b.s_force[k] = s_force;
        b.moment[k] = moment;
        b.knest[k] = knest;
        b.ksest[k] = ksest;
        b.krest[k] = krest;
        b.flags_out[k] = flags;
        if (flags & kFdEnergyOn)
            for (int e = 0; e < kEnergyCount; ++e) b.energy[e][k] = energy[e];
    }
};

/// The LaneLaw of model D (header comment). Its law catches what laneStep throws and declines
/// the contact (the host then runs FDlaw, which reports the failure).
template <class D>
const LaneLaw* laneLawOf() {
    struct Calls {
        static int32_t pack(const ContactModel* object, double* row) {
            return static_cast<const D*>(object)->toLane(row) ? 1 : 0;
        }
        static void unpack(ContactModel* object, const double* row) {
            static_cast<D*>(object)->fromLane(row);
        }
        static void law(const LaneBatch& b) {
            for (int32_t k = 0; k < b.count; ++k) {
                LaneFd fd = LaneFd::in(b, k);
                bool done = false;
                try {
                    done = D::laneStep(b.state + std::size_t{b.row[k]} * D::kLaneStateSize, fd);
                } catch (...) {
                    done = false;
                }
                if (done)
                    fd.out(b, k);
                else
                    b.flags_out[k] = kFdLaneDeclined;
            }
        }
    };
    static const LaneLaw law{sizeof(LaneLaw), D::kLaneStateSize, D::laneStateNames(),
                             &Calls::pack,    &Calls::unpack,    &Calls::law};
    return &law;
}

}  // namespace talus::sdk
