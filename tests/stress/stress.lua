-- SPDX-License-Identifier: MIT
-- The stress suite's runner (docs/stress.md). Run by the `talus` binary:
--
--   talus run stress.lua scenes FIRST COUNT [options]   seeded random scenes FIRST .. FIRST+COUNT-1
--   talus run stress.lua badinput [options]             the bad-input matrix over every Lua option
--   talus run stress.lua dump SEED [options]            the scene of SEED as a standalone script
--   talus run stress.lua selftest                       each check must catch a planted fault
--
-- Options: --budget=N (steps x balls per scene, default 600000), --max-balls=N, --model=NAME,
-- --kind=KIND, --progress (print "# seed N" before each scene, for the crash-detecting driver
-- scripts/bench/stress.sh), --verbose (also list the scenes that stopped or warned),
-- --out=DIR (scratch directory of the bad-input matrix).
--
-- Output: one "DEFECT ..." line per defect, then "stress: N scenes, M defects" (or
-- "stress: N bad-input cases, M defects"). Exit status 1 when there is a defect.
local gen = require("stress_gen")
local check = require("stress_check")

local args = { ... }
local mode = args[1]
local opts = { verbose = false, progress = false }
local pos = {}
for i = 2, #args do
    local k, v = args[i]:match("^%-%-([%w_-]+)=(.*)$")
    if k then
        opts[k] = v
    elseif args[i]:match("^%-%-") then
        opts[args[i]:sub(3)] = true
    else
        pos[#pos + 1] = args[i]
    end
end
local genopts = { budget = tonumber(opts.budget), max_balls = tonumber(opts["max-balls"]),
                  model = opts.model, kind = opts.kind }

local function usage()
    io.stderr:write("usage: talus run stress.lua scenes FIRST COUNT | badinput | dump SEED [--options]\n")
    os.exit(2)
end

if mode == "dump" then
    local seed = math.tointeger(tonumber(pos[1])) or usage()
    io.write(gen.dump(gen.scene(seed, genopts)))
elseif mode == "scenes" then
    local first = math.tointeger(tonumber(pos[1])) or usage()
    local count = math.tointeger(tonumber(pos[2])) or usage()
    local ndef, nstop, nwarn = 0, 0, 0
    local errors, warnings = {}, {}
    -- The kind of a message: a keyword of the engine's texts, else its first words.
    local kinds = { "non-finite", "energy created", "normal reversed", "under-resolved", "watchdog",
                    "stiffer", "overlap", "balance", "negative slip", "negative plastic",
                    "negative dashpot", "energy partition", "passing through", "became zero",
                    "gave back more energy", "fewer than" }
    local function kindOf(text)
        for _, k in ipairs(kinds) do if text:find(k, 1, true) then return k end end
        local t = text:gsub("^[^:]*:%d+: ", ""):gsub("%-?%d[%d.e+-]*", "#")
        return t:sub(1, 40)
    end
    -- FNV-1a (64 bit) over every scene's final state: one number to compare between builds
    -- (Release against a sanitizer build must give the same digest).
    local digest = 0xcbf29ce484222325
    local function mix(text)
        for i = 1, #text do digest = (digest ~ text:byte(i)) * 0x100000001b3 end
    end
    local nclump, ngroup, npart = 0, 0, 0
    local gworst = { own = 0, whole = 0, sum = 0 }
    local t0 = os.clock()
    local slowest = { first, 0 }
    for seed = first, first + count - 1 do
        if opts.progress then
            io.write("# seed ", seed, "\n")
            io.stdout:flush()
        end
        local S = gen.scene(seed, genopts)
        local c0 = os.clock()
        local defects, res = check.scene(S)
        if os.clock() - c0 > slowest[2] then slowest = { seed, os.clock() - c0 } end
        local desc = check.describe(S)
        if S.clumps then nclump = nclump + 1 end
        if S.groups then
            ngroup = ngroup + 1
            if res.partition_at_start then npart = npart + 1 end
            for _, r in pairs(res.groups or {}) do
                -- The largest group residual against the group's own throughput and against the
                -- model's (docs/stress.md "Group checks"), over the scenes the check applies to.
                if not res.err and #res.warnings == 0 and r.throughput > 0 and res.throughput > 0 then
                    local own, whole = math.abs(r.worst) / r.throughput, math.abs(r.worst) / res.throughput
                    if own > gworst.own then gworst.own, gworst.own_seed = own, seed end
                    if whole > gworst.whole then gworst.whole, gworst.whole_seed = whole, seed end
                end
            end
            if res.sum_worst and res.throughput > 0 and res.sum_worst / res.throughput > gworst.sum then
                gworst.sum, gworst.sum_seed = res.sum_worst / res.throughput, seed
            end
        end
        mix(res.state or "")
        mix((res.err or ""):gsub("^[^:]*:%d+: ", "")) -- the runner's path is not state
        for _, d in ipairs(defects) do
            print("DEFECT " .. desc .. " " .. d)
            ndef = ndef + 1
        end
        if res.err then
            nstop = nstop + 1
            local k = kindOf(res.err)
            errors[k] = (errors[k] or 0) + 1
            if opts.verbose then print("NOTE " .. desc .. " stopped: " .. res.err) end
        end
        if #res.warnings > 0 then
            nwarn = nwarn + 1
            local k = kindOf(res.warnings[1])
            warnings[k] = (warnings[k] or 0) + 1
            if opts.verbose then print("NOTE " .. desc .. " warned (" .. #res.warnings .. "): " .. res.warnings[1]) end
        end
        io.stdout:flush()
    end
    local function list(t)
        local keys = {}
        for k in pairs(t) do keys[#keys + 1] = k end
        table.sort(keys)
        local out = {}
        for _, k in ipairs(keys) do out[#out + 1] = string.format("%s x%d", k, t[k]) end
        return #out > 0 and table.concat(out, "; ") or "none"
    end
    print(string.format("stress: state digest %016x", digest))
    print(string.format("stress: seeds %d-%d, %.1f s CPU (slowest: seed %d, %.2f s for both runs); %d stopped with an error (%s); %d warned (%s)",
        first, first + count - 1, os.clock() - t0, slowest[1], slowest[2], nstop, list(errors), nwarn, list(warnings)))
    print(string.format("stress: %d scenes with clumps, %d with groups (%d partitions); worst group residual %.3g of its own throughput (seed %s), %.3g of the model's (seed %s); worst partition sum %.3g of the throughput (seed %s)",
        nclump, ngroup, npart, gworst.own, tostring(gworst.own_seed), gworst.whole, tostring(gworst.whole_seed), gworst.sum, tostring(gworst.sum_seed)))
    -- The same, as key=value for scripts/bench/stress.sh.
    print(string.format("stress: groupstats clumps=%d groups=%d partitions=%d own=%.3g own_seed=%s whole=%.3g whole_seed=%s sum=%.3g sum_seed=%s",
        nclump, ngroup, npart, gworst.own, tostring(gworst.own_seed), gworst.whole, tostring(gworst.whole_seed), gworst.sum, tostring(gworst.sum_seed)))
    print(string.format("stress: %d scenes, %d defects", count, ndef))
    os.exit(ndef > 0 and 1 or 0)
elseif mode == "badinput" then
    local bad = require("stress_badinput")
    local ncase, ndef, classes = bad.run(opts)
    print("stress: bad-input classes: " .. classes)
    print(string.format("stress: %d bad-input cases, %d defects", ncase, ndef))
    os.exit(ndef > 0 and 1 or 0)
elseif mode == "selftest" then
    -- A check that cannot fail is no check: plant one fault per check in a clean scene and
    -- require the checker to report it (and nothing in the clean scene itself). The engine's own
    -- balance check is off here, so that the planted energy fault is not announced.
    local gen_ = require("stress_gen")
    local function base()
        return { guard = gen_.hasGuardOption("balance") and { balance = "off" } or nil, seed = 0, kind = "free", model = "linear", mass = "disk", gravity = { 0, 0 },
                 props = { kn = 1e6, ks = 1e6, fric = 0.5 }, walls = {}, steps = 2000, chunks = 10,
                 balls = { { pos = { 0, 0 }, radius = 0.1, density = 1000, vel = { 1, 0 } },
                           { pos = { 0.5, 0.01 }, radius = 0.1, density = 1000, vel = { -1, 0 } } } }
    end
    local runs = 0
    local faults = {
        { "none", nil },
        -- Energy created outside every booking: a callback pushes the balls deeper into their
        -- contact (a velocity the script sets is booked, as `script`; the strain of a move into
        -- a contact is not). The contact then gives back more than it took: the guard's
        -- per-contact check is off too, as the balance check is.
        { "energy", function(m)
            m:guard{ energy = "off" }
            m:on_cycle(function(mm)
                if mm:contact_count{} == 0 then return end
                local mid, n = 0, 0
                for b in mm:balls() do mid, n = mid + b.pos[1], n + 1 end
                mid = mid / n
                for b in mm:balls() do
                    local p = b.pos
                    b.pos = { p[1] + (p[1] < mid and 1e-3 or -1e-3), p[2] }
                end
            end, 10)
        end },
        -- A run that differs from the previous one (a force that depends on the run count).
        { "determinism", function(m)
            runs = runs + 1
            local b = m:balls()()
            b.fapp = { runs * 1e-3, 0 }
        end },
        -- An error raised outside the m:cycle line, naming nothing.
        { "error", function(m) m:on_cycle(function() error("planted fault") end, 100) end },
    }
    local failed = 0
    for _, f in ipairs(faults) do
        local S = base()
        S.hook = f[2]
        local defects = check.scene(S)
        local kinds = {}
        for _, d in ipairs(defects) do kinds[#kinds + 1] = d:match("^(%a+)") end
        local found = table.concat(kinds, ",")
        local ok = (f[1] == "none" and #defects == 0) or (f[1] ~= "none" and found:find(f[1], 1, true) ~= nil)
        print(string.format("selftest %-12s %s (reported: %s)", f[1], ok and (f[1] == "none" and "clean" or "caught") or "MISSED", found == "" and "nothing" or found))
        if not ok then failed = failed + 1 end
    end
    print(string.format("stress: %d selftests, %d defects", #faults, failed))
    os.exit(failed > 0 and 1 or 0)
else
    usage()
end
