// SPDX-License-Identifier: MIT
#include "props.hpp"

#include <cctype>
#include <cmath>

#include "talus/errors.hpp"

namespace talus {

namespace {
std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}
}  // namespace

int32_t propIndex(const ContactModel& m, const std::string& name) {
    const std::string key = lower(name);
    for (int32_t i = 0; i < m.PropCount(); ++i) {
        const PropInfo* info = m.PropInfoAt(i);
        if (info && lower(info->name) == key) return i;
    }
    return -1;
}

std::string knownProps(const ContactModel& m) {
    std::string out;
    for (const char* c = m.PropNames(); c && *c; ++c)
        out += (*c == ',') ? std::string(", ") : std::string(1, *c);
    return out;
}

std::string propValueProblem(const ContactModel& model, int32_t index, double value) {
    if (std::isnan(value)) return "must be a number (got nan)";
    // A stiffness or modulus of +-inf makes every force and the step non-finite (the plugin's
    // range check may allow it: `power`'s transition force is legitimately inf).
    const PropInfo* info = model.PropInfoAt(index);
    const std::string units = info && info->units ? info->units : "";
    // A stress of +inf is a strength out of reach (pbond's pb_ten, pb_coh: an unbreakable
    // bond), so it goes to the model, whose range check or AcceptProp decides (a modulus in Pa
    // has a finite upper bound there: hertz, ng, pbond's emod); -inf is no stress.
    const bool stiffness = units == "N/m" || units == "N m/rad";
    if (std::isinf(value) && (stiffness || (units == "Pa" && value < 0.0)))
        return std::string("must be finite (got ") + (value > 0 ? "inf" : "-inf") + " " + units +
               ")";
    return {};
}

void applyProps(ContactModel& model, const std::vector<PropValue>& props,
                const std::string& where) {
    for (const auto& pv : props) {
        const int32_t idx = propIndex(model, pv.name);
        if (idx < 0)
            throw InputError(where + ": unknown property '" + pv.name + "' for model '" +
                             model.Name() + "' (known: " + knownProps(model) + ")");
        // NaN is no value (the PropBlock uses it for "not set"); a plugin's own range check may
        // not catch it, since every comparison with NaN is false.
        if (const std::string why = propValueProblem(model, idx, pv.value); !why.empty())
            throw InputError(where + ": " + model.Name() + ": '" + pv.name + "' " + why);
        int32_t status;
        try {
            status = model.AcceptProp(idx, pv.value);
        } catch (const std::exception& e) {
            throw PluginError(where + ": model '" + model.Name() +
                              "' threw from AcceptProp: " + e.what());
        }
        if (status != 0) throw InputError(where + ": " + model.LastError());
    }
}

PropBlock emptyPropBlock() {
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    for (int i = 0; i < 2; ++i) pb.kn[i] = pb.ks[i] = pb.fric[i] = kNotSet;
    return pb;
}

}  // namespace talus
