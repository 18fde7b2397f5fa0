// SPDX-License-Identifier: MIT
//
// Save and restore of a whole model (docs/save-format.md). The file is a fixed header (magic,
// format version, byte-order mark, payload length, FNV-1a checksum of the payload) and a payload
// of tagged sections: the engine's version (HEAD), the engine's sections, each written and read
// by the store it belongs to (save/sections.hpp: the table, one file per section), and the
// host's opaque section (HOST). Everything a cycle reads is saved as it is in memory, down to the
// order of the pairs and the broadphase trees' nodes, because the order in which contact forces
// are summed decides the last bits of every result: a restored model continues bit-identically
// (tests/scripting/save_restore/). The reader checks every count, index and enum before use.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "api/operations.hpp"
#include "save/sections.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/save_file.hpp"

#ifndef TALUS_ENGINE_VERSION
#error "TALUS_ENGINE_VERSION must be defined by the build (project version)"
#endif

namespace talus {

// ------------------------------------------------------------------------ the engine's sections

void Model::saveState(SaveWriter& w) const {
    checkSavable(*m_world);
    for (const SaveSection& s : engineSections()) {
        w.beginSection(s.tag);
        s.write(*m_world, w);
        w.endSection();
    }
    // Not a row of the table: written only when the model has servos (api/save_servos.cpp).
    saveServos(*m_world, w);
}

std::unique_ptr<Model> Model::restoreState(SaveReader& in, PluginRegistry& registry,
                                           std::vector<std::string>& notes) {
    auto mp = std::make_unique<Model>(ModelDef{}, registry);
    RestoreContext ctx{*mp->m_world, registry, notes};
    for (const SaveSection& s : engineSections()) {
        if (in.version() < s.since) continue;  // an older file: the store keeps a new model's
        SaveReader r = in.section(s.tag);
        s.read(ctx, r);
    }
    if (in.nextSection("SRVG")) restoreServos(*mp->m_world, in);
    return mp;
}

// ------------------------------------------------------------------------ the file

std::vector<uint8_t> saveModelBytes(const Model& model, const std::vector<uint8_t>& host) {
    SaveWriter w;
    w.bytes(kSaveMagic, 8);
    w.u32(kSaveFormatVersion);
    w.u32(kSaveByteOrderMark);
    w.u64(0);  // payload length, patched below
    w.u64(0);  // checksum, patched below
    w.beginSection("HEAD");
    w.str(TALUS_ENGINE_VERSION);
    w.endSection();
    model.saveState(w);
    w.beginSection("HOST");
    w.bytes(host.data(), host.size());
    w.endSection();
    w.bytes("END.", 4);
    auto& d = w.data();
    const uint64_t len = d.size() - kSaveHeaderSize;
    const uint64_t sum = fnv1a64(d.data() + kSaveHeaderSize, len);
    std::memcpy(d.data() + 16, &len, 8);
    std::memcpy(d.data() + 24, &sum, 8);
    return std::move(d);
}

void saveModelFile(const Model& model, const std::string& path, const std::vector<uint8_t>& host) {
    const std::vector<uint8_t> bytes = saveModelBytes(model, host);
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError("save: cannot write '" + tmp + "': " + std::strerror(errno));
    const bool ok =
        std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
    const int err = errno;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(tmp.c_str());
        throw InputError("save: cannot write '" + tmp + "': " + std::strerror(ok ? errno : err));
    }
    // rename() replaces `path` atomically: a crash before this line leaves the old file.
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw InputError("save: cannot rename '" + tmp + "' to '" + path +
                         "': " + std::strerror(e));
    }
}

RestoredModel restoreModelBytes(const uint8_t* data, std::size_t size, const std::string& name,
                                PluginRegistry& registry, bool verify_checksum) {
    SaveReader file(data, size, "'" + name + "'");
    if (size == 0) file.fail("empty file (not a Talus save file)");
    const std::size_t magic_have = std::min<std::size_t>(size, 8);
    if (std::memcmp(data, kSaveMagic, magic_have) != 0)
        file.fail("not a Talus save file (it does not start with \"TALUSSAV\")");
    if (size < kSaveHeaderSize)
        file.fail("truncated: " + std::to_string(size) + " bytes, shorter than the " +
                  std::to_string(kSaveHeaderSize) + "-byte header");
    char magic[8];
    file.bytes(magic, 8);
    const uint32_t format = file.u32();
    const uint32_t bom = file.u32();
    if (bom != kSaveByteOrderMark) {
        uint32_t swapped = __builtin_bswap32(bom);
        file.fail(swapped == kSaveByteOrderMark
                      ? "written on a machine of the other byte order (not supported)"
                      : "corrupted header (byte-order mark)");
    }
    if (format < 1 || format > kSaveFormatVersion)
        file.fail("save format version " + std::to_string(format) + "; this build of Talus (" +
                  TALUS_ENGINE_VERSION + ") reads version" +
                  (kSaveFormatVersion > 1 ? "s 1 to " : " ") + std::to_string(kSaveFormatVersion));
    file.setVersion(format);
    const uint64_t len = file.u64();
    const uint64_t sum = file.u64();
    if (len != size - kSaveHeaderSize)
        file.fail(len > size - kSaveHeaderSize
                      ? "truncated: the header announces " + std::to_string(len) +
                            " bytes of data, the file has " + std::to_string(size - kSaveHeaderSize)
                      : "corrupted: " + std::to_string(size - kSaveHeaderSize - len) +
                            " bytes more than the header announces");
    if (verify_checksum && fnv1a64(data + kSaveHeaderSize, len) != sum)
        file.fail("corrupted: the checksum does not match the data");

    RestoredModel out;
    {
        SaveReader r = file.section("HEAD");
        out.engine_version = r.str();
        r.expectEnd();
    }
    if (out.engine_version != TALUS_ENGINE_VERSION)
        out.notes.push_back("saved by Talus " + out.engine_version + "; this is Talus " +
                            TALUS_ENGINE_VERSION);
    out.model = Model::restoreState(file, registry, out.notes);
    {
        SaveReader r = file.section("HOST");
        out.host.resize(r.left());
        r.bytes(out.host.data(), out.host.size());
    }
    char end[4];
    file.bytes(end, 4);
    if (std::memcmp(end, "END.", 4) != 0) file.fail("corrupted end marker");
    file.expectEnd();
    return out;
}

RestoredModel restoreModelFile(const std::string& path, PluginRegistry& registry) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError("restore: cannot open '" + path + "': " + std::strerror(errno));
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)),
                               std::istreambuf_iterator<char>());
    if (f.bad()) throw InputError("restore: cannot read '" + path + "'");
    return restoreModelBytes(bytes.data(), bytes.size(), path, registry, true);
}

}  // namespace talus
