// SPDX-License-Identifier: MIT
// talus.map's checkpoint files (map_checkpoint.hpp).
#include "map_checkpoint.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "lua_runtime.hpp"
#include "map_codec.hpp"
#include "progress.hpp"

namespace talus::lua {

namespace {

const std::string kMagic = "talus.map item 2\n";
const std::string kMagicV1 = "talus.map item\n";  // before the checksum: read, never written

std::string put64(uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);
    return std::string(b, 8);
}

uint64_t get64(const std::string& s, std::size_t at) {
    uint64_t v = 0;
    std::memcpy(&v, s.data() + at, 8);
    return v;
}

bool startsWith(const std::string& s, const std::string& prefix) {
    return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

/// The key and the value after the key's length at `at`: Taken, OtherKey or Damaged.
Checkpoint::Item keyAndValue(const std::string& bytes, std::size_t at, const std::string& key,
                             std::string& value, std::string& why) {
    if (bytes.size() - at < 8) return why = "truncated", Checkpoint::Item::Damaged;
    const uint64_t klen = get64(bytes, at);
    at += 8;
    if (bytes.size() - at < klen) return why = "truncated", Checkpoint::Item::Damaged;
    value = bytes.substr(at + klen);
    if (!wellFormed(value.data(), value.size()))
        return why = "its value is not whole", Checkpoint::Item::Damaged;
    if (klen != key.size() || bytes.compare(at, klen, key) != 0) return Checkpoint::Item::OtherKey;
    return Checkpoint::Item::Taken;
}

}  // namespace

std::string Checkpoint::file(int64_t i) const {
    return dir + "/item_" + std::to_string(i) + ".tmv";
}

Checkpoint::Item Checkpoint::load(int64_t i, std::string& value, std::string& why) const {
    std::FILE* f = std::fopen(file(i).c_str(), "rb");
    if (!f) return Item::Missing;
    std::string bytes;
    char buf[1 << 16];
    std::size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, got);
    const bool read_error = std::ferror(f) != 0;
    std::fclose(f);
    if (read_error) return why = "it cannot be read", Item::Damaged;
    if (startsWith(bytes, kMagic)) {
        const std::size_t at = kMagic.size() + 8;
        if (bytes.size() < at) return why = "truncated", Item::Damaged;
        if (checksum64(bytes.data() + at, bytes.size() - at) != get64(bytes, kMagic.size()))
            return why = "its checksum does not match: changed or cut short", Item::Damaged;
        return keyAndValue(bytes, at, key, value, why);
    }
    if (startsWith(bytes, kMagicV1)) return keyAndValue(bytes, kMagicV1.size(), key, value, why);
    why = bytes.empty() ? "empty" : "not a talus.map item";
    return Item::Damaged;
}

void Checkpoint::open() const {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw ScriptError("map: cannot create the checkpoint directory '" + dir + "' (" +
                          ec.message() + ")");
}

std::vector<int64_t> Checkpoint::take(int64_t lo, int64_t hi, std::vector<std::string>& values,
                                      CheckpointCounts& counts) const {
    std::vector<int64_t> todo;
    std::string why;
    for (int64_t i = lo; i <= hi; ++i) {
        std::string& value = values[static_cast<std::size_t>(i - lo)];
        const Item item = on() ? load(i, value, why) : Item::Missing;
        if (item == Item::Taken) {
            ++counts.taken;
            continue;
        }
        value.clear();
        todo.push_back(i);
        counts.other_key += item == Item::OtherKey;
        if (item == Item::Damaged) {
            ++counts.damaged;
            clearProgressLine();
            std::fflush(stdout);
            std::fprintf(stderr,
                         "talus: map: the checkpoint file '%s' is damaged (%s); fn(%lld) runs "
                         "again\n",
                         file(i).c_str(), why.c_str(), static_cast<long long>(i));
        }
    }
    return todo;
}

void Checkpoint::store(int64_t i, const std::string& value) const {
    const std::string path = file(i), tmp = dir + "/.item_" + std::to_string(i) + ".tmp";
    const std::string body = put64(key.size()) + key + value;
    const std::string head = kMagic + put64(checksum64(body.data(), body.size()));
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    bool ok = f != nullptr;
    if (ok) {
        ok = std::fwrite(head.data(), 1, head.size(), f) == head.size() &&
             std::fwrite(body.data(), 1, body.size(), f) == body.size();
        ok = (std::fclose(f) == 0) && ok;
    }
    if (ok && std::rename(tmp.c_str(), path.c_str()) == 0) return;
    const int err = errno;
    std::remove(tmp.c_str());
    static bool said = false;
    if (!said) {
        said = true;
        std::fprintf(stderr,
                     "talus: warning: map: cannot write the checkpoint file '%s' (%s); the map "
                     "goes on, but a rerun will run such items again\n",
                     path.c_str(), std::strerror(err));
    }
}

}  // namespace talus::lua
