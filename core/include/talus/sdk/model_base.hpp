// SPDX-License-Identifier: MIT
//
// ModelBase<Derived>: the boilerplate of a contact model, so that a model file holds only its
// physics. It implements property access by name from a static table, range checks with readable
// messages, placement Clone/Destroy, SaveRestore of the properties, and an exception barrier
// around FDlaw (a model that throws reports an error instead of unwinding through the host).
//
// A model derives as `class Linear final : public talus::sdk::ModelBase<Linear>` and provides
//   static constexpr const char* kName;
//   static const talus::sdk::PropTable<Linear>& Table();
//   void fdlaw(talus::FdBlock& fd);                       // may throw std::exception
//   void saveRestoreState(talus::ModelSaveObject& so);     // per-contact state only
//   bool inherit(const talus::PropBlock& pb);              // set per-contact properties; false +
//                                                           // fail("...") on error
// and optionally
//   void onPropChanged();                                  // recompute cached derived values
// and overrides KnEstimate, KsEstimate and ContactDuration.
#pragma once

#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "talus/contact_model.hpp"

namespace talus::sdk {

/// One property: its public description, where it lives and its valid range.
template <class D>
struct PropSpec {
    PropInfo info;
    double D::*member;
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;              ///< true: value must be > lo (not >=)
    const char* range_note = nullptr;  ///< extra words for the range error (a citation)
};

template <class D>
using PropTable = std::vector<PropSpec<D>>;

constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
/// Upper bound for stiffnesses [N/m] and elastic moduli [Pa]: ten million times diamond's
/// modulus, far above any rock, and low enough that forces and energies (k u^2 / 2) of any
/// overlap a time step resolves stay finite in double precision (stress suite: 1e300 overflowed).
constexpr double kStiffnessMax = 1e20;
inline bool isSet(double v) { return !std::isnan(v); }

/// PFC inheritance of a stiffness: springs in series when both ends define it, the one value
/// when one end does, else the model's own value.
inline double inheritSeries(double own, const double ends[2]) {
    const bool a = isSet(ends[0]), b = isSet(ends[1]);
    if (a && b) return (ends[0] + ends[1]) > 0.0 ? ends[0] * ends[1] / (ends[0] + ends[1]) : 0.0;
    if (a) return ends[0];
    if (b) return ends[1];
    return own;
}

/// PFC inheritance of friction: the smaller of the ends' values, else the model's own.
inline double inheritMin(double own, const double ends[2]) {
    const bool a = isSet(ends[0]), b = isSet(ends[1]);
    if (a && b) return std::fmin(ends[0], ends[1]);
    if (a) return ends[0];
    if (b) return ends[1];
    return own;
}

/// Per-thread error text shared by all models of one library (LastError() returns it).
inline std::string& errorText() {
    static thread_local std::string text;
    return text;
}

template <class Derived>
class ModelBase : public ContactModel {
public:
    const char* Name() const override { return Derived::kName; }

    const char* PropNames() const override {
        static const std::string names = [] {
            std::string s;
            for (const auto& p : Derived::Table()) {
                if (!s.empty()) s += ",";
                s += p.info.name;
            }
            return s;
        }();
        return names.c_str();
    }

    int32_t PropCount() const override { return static_cast<int32_t>(Derived::Table().size()); }

    const PropInfo* PropInfoAt(int32_t index) const override {
        if (index < 0 || index >= PropCount()) return nullptr;
        return &Derived::Table()[static_cast<std::size_t>(index)].info;
    }

    double ReturnProp(int32_t index) const override {
        if (index < 0 || index >= PropCount()) return kUnset;
        return self().*(Derived::Table()[static_cast<std::size_t>(index)].member);
    }

    int32_t AcceptProp(int32_t index, double value) override {
        if (index < 0 || index >= PropCount()) return fail("property index out of range");
        const auto& p = Derived::Table()[static_cast<std::size_t>(index)];
        if (p.info.flags & kPropReadOnly)
            return fail(std::string("property '") + p.info.name + "' is read-only");
        if (const char* why = checkRange(p, value)) return fail(why);
        self().*(p.member) = value;
        self().onPropChanged();
        return 0;
    }

    const char* LastError() const override { return errorText().c_str(); }

    std::size_t ObjectSize() const override { return sizeof(Derived); }

    ContactModel* Clone(const PropBlock& pb, void* storage) const override {
        static_assert(alignof(Derived) <= alignof(std::max_align_t), "over-aligned model");
        Derived* copy = nullptr;
        try {
            copy = new (storage) Derived(self());
            if (!copy->inherit(pb)) {
                const std::string why = errorText();
                copy->~Derived();
                errorText() = why;
                return nullptr;
            }
        } catch (const std::exception& e) {
            if (copy) copy->~Derived();
            errorText() = e.what();
            return nullptr;
        }
        return copy;
    }

    void Destroy() override { self().~Derived(); }

    ContactModel* MoveTo(void* storage) override {
        Derived* moved = new (storage) Derived(std::move(self()));
        self().~Derived();
        return moved;
    }

    const char* PreCycle(const PropBlock&) override {
        for (const auto& p : Derived::Table()) {
            if (p.info.flags & kPropReadOnly) continue;
            if (const char* why = checkRange(p, self().*(p.member))) {
                errorText() = why;
                return errorText().c_str();
            }
        }
        return nullptr;
    }

    void FDlaw(FdBlock& fd) override {
        try {
            self().fdlaw(fd);
        } catch (const std::exception& e) {
            errorText() = e.what();
            fd.status = 1;
            fd.error = errorText().c_str();
        } catch (...) {
            errorText() = "unknown exception in FDlaw";
            fd.status = 1;
            fd.error = errorText().c_str();
        }
    }

    /// The batched law (contact_model.hpp, BatchFdLawFn): FDlaw over an array of contacts,
    /// with the same barrier, without a virtual call per contact. The law is the same inline
    /// code, so both paths give the same bits. A library offers it by exporting
    /// talus_plugin_batch (contact_model.hpp; plugins/linear/linear.cpp). It runs fdlaw()
    /// inside ModelBase's barrier: a model that overrides FDlaw itself must not offer it.
    static void BatchFDlaw(ContactModel* const* models, FdBlock* blocks, int32_t count) {
        for (int32_t k = 0; k < count; ++k)
            static_cast<Derived*>(models[k])->ModelBase::FDlaw(blocks[k]);
    }

    double ActivityDistance() const override { return 0.0; }
    bool OKToDelete() const override { return true; }
    uint32_t Traits() const override { return kTraitThreadSafe; }

    /// Saves or restores the settable properties, then the derived class's state.
    void SaveRestore(ModelSaveObject& so) override {
        for (const auto& p : Derived::Table())
            if (!(p.info.flags & kPropReadOnly)) so.Double(self().*(p.member));
        self().saveRestoreState(so);
        if (!so.IsSaving()) self().onPropChanged();
    }

    /// Called after a property changed (AcceptProp, restore): a derived model recomputes what it
    /// caches from its properties by declaring its own onPropChanged().
    void onPropChanged() {}

protected:
    static int32_t fail(const std::string& why) {
        errorText() = why;
        return 1;
    }

private:
    Derived& self() { return static_cast<Derived&>(*this); }
    const Derived& self() const { return static_cast<const Derived&>(*this); }

    static const char* checkRange(const PropSpec<Derived>& p, double v) {
        static thread_local char buf[320];
        const bool integer = (p.info.flags & kPropInteger) != 0;
        bool ok = std::isfinite(v) || (v == std::numeric_limits<double>::infinity() &&
                                       p.hi == std::numeric_limits<double>::infinity());
        if (ok) ok = p.lo_open ? v > p.lo : v >= p.lo;
        if (ok) ok = v <= p.hi;
        if (ok && integer) ok = std::floor(v) == v;
        if (ok) return nullptr;
        const char* op = p.lo_open ? ">" : ">=";
        if (integer && p.info.enum_names) {
            std::string names;
            for (int i = 0; p.info.enum_names[i]; ++i) {
                if (i) names += ", ";
                names += std::to_string(i) + " = " + p.info.enum_names[i];
            }
            std::snprintf(buf, sizeof buf, "%s: '%s' must be one of %s (got %g)", Derived::kName,
                          p.info.name, names.c_str(), v);
        } else if (p.hi == kStiffnessMax && v > p.hi) {
            std::snprintf(buf, sizeof buf,
                          "%s: '%s' must be <= %g %s (a stiffness beyond any material; forces and "
                          "energies would overflow) (got %g)",
                          Derived::kName, p.info.name, p.hi, p.info.units, v);
        } else if (p.hi == std::numeric_limits<double>::infinity() || p.hi == kStiffnessMax) {
            std::snprintf(buf, sizeof buf, "%s: '%s' must be %s %g%s%s (got %g)", Derived::kName,
                          p.info.name, op, p.lo, p.range_note ? " " : "",
                          p.range_note ? p.range_note : "", v);
        } else {
            std::snprintf(buf, sizeof buf, "%s: '%s' must be in %s%g, %g] %s(got %g)",
                          Derived::kName, p.info.name, p.lo_open ? "(" : "[", p.lo, p.hi,
                          p.range_note ? p.range_note : "", v);
        }
        return buf;
    }
};

}  // namespace talus::sdk
