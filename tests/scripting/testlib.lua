-- SPDX-License-Identifier: MIT
-- Small assertion helpers for the Lua API tests (run by `talus run`; a failed check raises an
-- error, so the test exits non-zero with the failing line).
local T = {}

T.checks = 0

function T.check(cond, what)
    T.checks = T.checks + 1
    if not cond then error("check failed: " .. tostring(what), 2) end
end

--- |a - b| <= tol * max(1, |b|) (relative for large values, absolute near zero).
function T.near(a, b, tol, what)
    T.checks = T.checks + 1
    if type(a) ~= "number" or type(b) ~= "number" or a ~= a or b ~= b
        or math.abs(a - b) > tol * math.max(1, math.abs(b)) then
        error(string.format("check failed: %s: got %.17g, expected %.17g (tol %g)", tostring(what),
            tonumber(a) or 0 / 0, tonumber(b) or 0 / 0, tol), 2)
    end
end

--- The line of the caller (to build the expected "file:line:" prefix of an error).
function T.line() return debug.getinfo(2, "l").currentline end

--- Calls fn, expects it to fail with a message containing every plain string in `parts`.
function T.fails(fn, parts, what)
    T.checks = T.checks + 1
    local ok, err = pcall(fn)
    if ok then error("check failed: " .. tostring(what) .. ": no error was raised", 2) end
    err = tostring(err)
    for _, p in ipairs(parts) do
        if not err:find(p, 1, true) then
            error(string.format("check failed: %s: message %q does not contain %q", tostring(what),
                err, p), 2)
        end
    end
    return err
end

--- Name of this test script as it appears in error positions (the chunk name).
function T.script() return debug.getinfo(2, "S").short_src end

--- A value written exactly: numbers as hexadecimal floats (%a), arrays as {a,b,...}; for state
--- dumps compared byte for byte (save/restore continuation).
function T.hex(v)
    if type(v) == "number" then return string.format("%a", v) end
    if type(v) == "table" then
        local parts = {}
        for i = 1, #v do parts[#parts + 1] = T.hex(v[i]) end
        return "{" .. table.concat(parts, ",") .. "}"
    end
    return tostring(v)
end

--- A model's state written exactly (T.hex), for runs compared bit for bit: every ball's position,
--- velocity and spin; every contact's key, forces and overlap with the contact-model properties
--- named in `opts.props`; the energy items named in `opts.energies`; with `opts.walls`, every
--- wall's first vertex and velocity; the time.
function T.state_text(m, opts)
    opts = opts or {}
    local out = {}
    local function put(...) for _, v in ipairs({...}) do out[#out + 1] = T.hex(v) end end
    for b in m:balls() do put(b.pos[1], b.pos[2], b.vel[1], b.vel[2], b.spin) end
    for c in m:contacts{} do
        out[#out + 1] = tostring(c.key)
        put(c.normal_force, c.shear_force, c.overlap)
        for _, k in ipairs(opts.props or {}) do put(c:prop(k)) end
    end
    if opts.energies then
        local e = m:energies()
        for _, k in ipairs(opts.energies) do put(e[k]) end
    end
    if opts.walls then
        for w in m:walls() do put(w.points[1][1], w.points[1][2], w.vel[1], w.vel[2]) end
    end
    put(m:time())
    return table.concat(out, " ")
end

--- The small flat-jointed specimen of the regression tests (about 120 balls, 1 x 2 cm; the
--- material library's genesis with packing seed `seed`): its packing, material table and the
--- contact modulus.
function T.small_fjoint(seed)
    local M = require("material")
    local emod = 6.4e10
    local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                          kn = emod, ks = emod / 2.5, seed = seed }
    local mat = { model = "fjoint", kn = emod, ks = emod / 2.5, fric = 0.5, density = 2600,
                  bond = { fj_emod = emod, fj_kratio = 2.5, fj_nr = 2, fj_fric = 0.6, fj_fa = 0,
                           fj_ten = { mean = 2e7, sd = 2e6, dist = "normal" },
                           fj_coh = { mean = 1e8, sd = 1e7, dist = "normal" } } }
    return pk, mat, emod
end

--- A reproducible stream of numbers in [0, 1) from `seed` (the C library's classic linear
--- congruential rule, the same on every platform): scenes that place balls "at random" the
--- same way in every run.
function T.lcg(seed)
    return function()
        seed = (seed * 1103515245 + 12345) % 2147483648
        return seed / 2147483648
    end
end

--- The keys of a table, sorted.
function T.sorted_keys(t)
    local keys = {}
    for k in pairs(t) do keys[#keys + 1] = k end
    table.sort(keys)
    return keys
end

--- A digest of a value: every field of every table in a fixed order, numbers to 17 digits,
--- hashed with FNV-1a (64 bits; Lua's integers wrap around). Equal digests, equal records.
function T.digest(value)
    local out = {}
    local function serialize(v)
        if type(v) == "number" then
            out[#out + 1] = math.type(v) == "integer" and string.format("%d", v) or string.format("%.17g", v)
        elseif type(v) == "table" then
            local keys = {}
            for k in pairs(v) do keys[#keys + 1] = k end
            table.sort(keys, function(a, b)
                if type(a) == type(b) then return a < b end
                return type(a) == "number"
            end)
            out[#out + 1] = "{"
            for _, k in ipairs(keys) do
                out[#out + 1] = tostring(k) .. "="
                serialize(v[k])
                out[#out + 1] = ","
            end
            out[#out + 1] = "}"
        else
            out[#out + 1] = tostring(v)
        end
    end
    serialize(value)
    local text = table.concat(out)
    local h = -3750763034362895579 -- 0xcbf29ce484222325
    for i = 1, #text do h = (h ~ text:byte(i)) * 0x100000001b3 end
    return string.format("%016x", h)
end

--- A resting scene's books: switches tracing on, runs `steps` steps to let the start settle and
--- `steps` more; returns the energies after each half and the model's first contact.
function T.rest_books(m, steps)
    m:energy{ on = true }
    m:cycle(steps)
    local e1 = m:energies()
    m:cycle(steps)
    return e1, m:energies(), m:contacts{}()
end

function T.done(name)
    print(string.format("%s: %d checks passed", name, T.checks))
end

return T
