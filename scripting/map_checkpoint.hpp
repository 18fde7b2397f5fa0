// SPDX-License-Identifier: MIT
//
// talus.map's checkpoint (the `checkpoint` and `key` options): every finished value is kept on
// disk as it arrives, one file per item, so that a rerun of the same map, after a failure or a
// killed job, runs only what is missing. `<dir>/item_<i>.tmv`, written through a temporary
// file and a rename (a half-written file is never taken):
//
//     "talus.map item 2\n"  | FNV-1a 64 of the rest (8 bytes) | key length (8) | key | value
//
// the value in map_codec's format, integers in the machine's byte order. The checksum makes a
// damaged file (a flipped bit, a cut) known for what it is: its item is run again, with a note
// naming the file. Items written before the checksum ("talus.map item\n", the key length, the
// key, the value) are still read; of those only the structure of the value can be checked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace talus::lua {

/// What a map found in its checkpoint (summed over the ranks for the closing note).
struct CheckpointCounts {
    int64_t taken = 0;      ///< items taken from the checkpoint, not run
    int64_t other_key = 0;  ///< files of another run (another key): their items run again
    int64_t damaged = 0;    ///< damaged files: their items run again

    bool any() const { return taken > 0 || other_key > 0 || damaged > 0; }
    CheckpointCounts& operator+=(const CheckpointCounts& o) {
        taken += o.taken;
        other_key += o.other_key;
        damaged += o.damaged;
        return *this;
    }
};

struct Checkpoint {
    std::string dir;  ///< "" = none
    std::string key;

    bool on() const { return !dir.empty(); }
    std::string file(int64_t i) const;

    /// What load() found for an item.
    enum class Item {
        Missing,   ///< no file: the item runs
        Taken,     ///< a whole item of this key: `value` holds it
        OtherKey,  ///< a whole item stored by another run (another key): the item runs again
        Damaged,   ///< not a whole item (`why` says how): the item runs again
    };
    Item load(int64_t i, std::string& value, std::string& why) const;

    /// Creates the directory (and its parents); throws ScriptError saying why it cannot.
    void open() const;

    /// Takes the items of [lo, hi] held whole under this key into values[i - lo] and returns the
    /// others, to be run (all of them without a checkpoint). A damaged file is said on stderr,
    /// naming it, and its item runs again.
    std::vector<int64_t> take(int64_t lo, int64_t hi, std::vector<std::string>& values,
                              CheckpointCounts& counts) const;

    /// Stores item i's value; a failure to write is reported once on stderr and the map goes on
    /// (the results are still returned; only a rerun loses them).
    void store(int64_t i, const std::string& value) const;
};

}  // namespace talus::lua
