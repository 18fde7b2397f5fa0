// SPDX-License-Identifier: MIT
// Loads contact-model plugins with dlopen and hands out their prototypes by model name.
// Libraries stay loaded until the registry is destroyed at exit (so no library is unloaded
// while objects it made are alive); prototypes are destroyed first, by the library's own code.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"

namespace talus {

/// One model a plugin library offers.
struct ModelFactory {
    std::string name;     ///< ContactModel::Name()
    std::string library;  ///< path of the shared library
    std::string plugin_version;
    int32_t index = 0;  ///< index for PluginInfo::create_prototype
    const PluginInfo* info = nullptr;
    /// Read-only prototype for metadata (property names, defaults); never cloned.
    ContactModel* reference = nullptr;
    /// The model's batched FDlaw (talus_plugin_batch), or nullptr: FDlaw per contact.
    BatchFdLawFn batch = nullptr;
    /// The model's lane law (talus_plugin_lanes, ABI 1.2), or nullptr: no lanes.
    const LaneLaw* lanes = nullptr;
    /// The SDK law the model runs on its lane rows (talus_plugin_kernel, ABI 1.3), or empty.
    std::string kernel;
};

/// Most doubles of state per contact a lane law may declare (LaneLaw::state_size).
constexpr int32_t kMaxLaneStateSize = 256;

class PluginRegistry {
public:
    PluginRegistry();
    ~PluginRegistry();
    PluginRegistry(const PluginRegistry&) = delete;
    PluginRegistry& operator=(const PluginRegistry&) = delete;

    /// The process-wide registry (searching TALUS_PLUGIN_PATH until the host appends more).
    static PluginRegistry& global();

    /// Loads a library; returns the names of the models it added. Loading the same file twice
    /// is a no-op. Throws PluginError naming the file for every refusal.
    std::vector<std::string> load(const std::string& path);

    /// Finds a model by name (case-insensitive), loading `libtalus_<name>.so` from the search
    /// path if needed. Throws PluginError listing the known models if there is none.
    const ModelFactory& find(const std::string& name);
    const ModelFactory* tryFind(const std::string& name) const;

    /// Directories searched by find(), in order: those added with addSearchDirectory, then
    /// TALUS_PLUGIN_PATH's (colon-separated, read when the registry is created), then those
    /// appended by the host program (the talus command appends its shipped plugin directory,
    /// found beside its executable), so that a user's directory overrides a shipped model.
    void addSearchDirectory(const std::string& dir);
    void appendSearchDirectory(const std::string& dir);
    const std::vector<std::string>& searchDirectories() const { return m_dirs; }
    std::vector<std::string> modelNames() const;

    /// Creates a fresh prototype (owned by the caller through the deleter).
    struct PrototypeDeleter {
        const PluginInfo* info = nullptr;
        void operator()(ContactModel* p) const;
    };
    using PrototypePtr = std::unique_ptr<ContactModel, PrototypeDeleter>;
    PrototypePtr createPrototype(const ModelFactory& f) const;

private:
    struct Library;
    std::vector<std::unique_ptr<Library>> m_libraries;
    // A deque: loading another plugin appends without moving the factories, so a contact
    // rule's pointer to its factory stays valid (Model::Rule::factory).
    std::deque<ModelFactory> m_models;
    std::vector<std::string> m_dirs;
};

}  // namespace talus
