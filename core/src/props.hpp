// SPDX-License-Identifier: MIT
// Contact-model properties by name (case-insensitive), shared by the model and the rig.
#pragma once

#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/model.hpp"

namespace talus {

/// Index of the property `name` (case-insensitive), or -1.
int32_t propIndex(const ContactModel& m, const std::string& name);
/// "kn, ks, fric, ..." for error messages.
std::string knownProps(const ContactModel& m);
/// Sets each property by name; throws InputError naming `where`, the model and the property.
/// Why `value` is no valid input for property `index` (NaN; an infinite stiffness or modulus),
/// or empty; the model's own AcceptProp checks its range afterwards.
std::string propValueProblem(const ContactModel& model, int32_t index, double value);
void applyProps(ContactModel& model, const std::vector<PropValue>& props, const std::string& where);
/// A PropBlock with nothing inherited.
PropBlock emptyPropBlock();

}  // namespace talus
