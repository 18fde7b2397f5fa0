-- SPDX-License-Identifier: MIT
--
-- single_rock.lua: one rock down the stepped slope profile of Nejati (2008).
--
--   talus run scripts/examples/single_rock.lua [outdir] [--kn=1e8] [--rn=0.35] [--tan_beta=0.30]
--                                           [--no-rolling]
--
-- Writes <outdir>/rockfall_history.csv (time, x, y, vx, vy, spin and the energies) and
-- <outdir>/rockfall_slope.csv (the slope profile, x and y; scripts/plot_history.py plots both,
-- see the end of this file), and prints a summary: run-out, impacts, bounce height, final
-- position, energy balance, which time-step rule governed, and the run-out against the
-- empirical shadow-angle bound.
--
-- Inputs (docs/getting-started.md discusses them):
--   rock      disk (unit thickness, PFC2D), R = 0.5 m, density 2600 kg/m^3, m = 2042 kg,
--             released at (R, 60 + R) with velocity (3, -2) m/s (Nejati 2008);
--   slope     (0,60) (7.3,40) (19.3,40) (26.2,20) (38.6,20) (46,0) (170,0), one wall;
--   contact   linear model. kn = 1e8 N/m: Nejati (2008) used 1e6-1e7 N/m for walls, but for a
--             2042 kg disk 1e7 N/m lets a 20 m/s impact overlap by 0.29 m (57% of R); 1e8 N/m
--             keeps it near 0.09 m. ks = kn / 2, fric = 0.5.
--             Normal restitution Rn = 0.35, "bedrock outcrops" in the RocFall defaults
--             (RocFall's classic default materials): dp_nratio = -ln(Rn) / sqrt(pi^2 + ln(Rn)^2) = 0.317, full
--             dashpot mode, so e = exp(-pi beta / sqrt(1 - beta^2)) holds (accuracy-ref. 1.1).
--   rolling   the rrlinear model (docs/models/rrlinear.md): the linear model plus a rolling
--             moment limited to rr_fric R Fn, with rr_fric = (1 + I/(m R^2)) tan(beta) so
--             that a rolling disk decelerates at g tan(beta), the rolling friction of STONE;
--             tan(beta) = 0.30 for bedrock (STONE, Guzzetti et al. 2002). --no-rolling switches it
--             off (rr_fric = 0), --tan_beta= changes it. Its work is booked as slip.
--             For many rocks, shapes, materials and statistics see rockfall_analysis.lua.
--
-- With these inputs the rock glances off the first cliff face, lands at its toe and stays on
-- the first bench (benches catch rocks). --tan_beta=0.05 lets it roll down to the bottom flat;
-- --no-rolling lets it roll off the end of the profile, which the shadow-angle check flags.

-- ------------------------------------------------------------------ arguments

local outdir, kn, rn, rolling, tan_beta = "out", 1e8, 0.35, true, 0.30
for _, a in ipairs(arg) do
    local key, value = a:match("^%-%-([%w_]+)=(.+)$")
    if key == "kn" then kn = assert(tonumber(value), "--kn needs a number")
    elseif key == "rn" then rn = assert(tonumber(value), "--rn needs a number")
    elseif key == "tan_beta" then tan_beta = assert(tonumber(value), "--tan_beta needs a number")
    elseif a == "--no-rolling" then rolling = false
    elseif a:match("^%-%-") then error("unknown option " .. a .. " (--kn=, --rn=, --tan_beta=, --no-rolling)")
    else outdir = a end
end
talus.mkdir(outdir)

-- ------------------------------------------------------------------ scene

local profile = { {0, 60}, {7.3, 40}, {19.3, 40}, {26.2, 20}, {38.6, 20}, {46, 0}, {170, 0} }
local R, density = 0.5, 2600
local beta = -math.log(rn) / math.sqrt(math.pi ^ 2 + math.log(rn) ^ 2)

local m = talus.model{ gravity = {0, -9.81}, mass = "disk" }
-- The contact model (rrlinear) is set below, once the rock's mass and inertia give rr_fric.
m:wall{ points = profile, group = "slope" }
local rock = m:ball{ pos = {R, 60 + R}, radius = R, density = density, vel = {3, -2}, group = "rock" }
-- A wide broadphase margin lets the free-flight steps grow (the kinematic rule keeps each body
-- inside its fat box); impacts are still resolved by the resolution rule (30 steps each).
m:broadphase{ margin = R }
m:energy{ on = true }

local x_end = profile[#profile][1]
local function ground(x)  -- height of the profile under x
    for k = 1, #profile - 1 do
        local a, b = profile[k], profile[k + 1]
        if x <= b[1] then
            if b[1] == a[1] then return math.min(a[2], b[2]) end
            return a[2] + (b[2] - a[2]) * (math.max(x, a[1]) - a[1]) / (b[1] - a[1])
        end
    end
    return profile[#profile][2]
end

-- ------------------------------------------------------------------ history and statistics

local history = m:history{
    file = outdir .. "/rockfall_history.csv", every = 10,
    columns = {
        "time",
        { "x", function() return rock.pos[1] end },
        { "y", function() return rock.pos[2] end },
        { "vx", function() return rock.vel[1] end },
        { "vy", function() return rock.vel[2] end },
        { "spin", function() return rock.spin end },
        "kinetic", "body", "slip", "dashpot", "balance_error",
    },
}

local mass, inertia = rock.mass, rock.inertia
local mu_r = rolling and (1 + inertia / (mass * R * R)) * tan_beta or 0
m:contact_model("rrlinear", { kn = kn, ks = kn / 2, fric = 0.5, dp_nratio = beta, dp_mode = "full", rr_fric = mu_r })
local stats = {
    impacts = {}, touches = 0, touching = false, max_bounce = 0, max_bounce_x = 0,
    max_overlap = 0, rules = {}, max_speed = 0,
}
m:on_cycle(function(model)
    local normal_force, contact = 0, nil
    for c in model:contacts{ ball = rock } do
        normal_force = normal_force + math.max(c.normal_force, 0)
        stats.max_overlap = math.max(stats.max_overlap, c.overlap)
        contact = c
    end
    local pos, vel = rock.pos, rock.vel
    if contact and not stats.touching then
        -- A new touch: an impact if it arrives with some speed (rolling re-touches do not count).
        stats.touches = stats.touches + 1
        local n = contact.normal
        local vn = math.abs(vel[1] * n[1] + vel[2] * n[2])
        if vn > 0.5 then
            stats.impacts[#stats.impacts + 1] = { t = model:time(), x = pos[1], vn = vn }
        end
    end
    stats.touching = contact ~= nil
    if not contact then
        local h = pos[2] - R - ground(pos[1])
        -- Bounce heights count after the first touch (the fall off the crest is not a bounce).
        if h > stats.max_bounce and stats.touches > 0 then
            stats.max_bounce, stats.max_bounce_x = h, pos[1]
        end
    end
    stats.max_speed = math.max(stats.max_speed, math.sqrt(vel[1] ^ 2 + vel[2] ^ 2))
    if pos[1] > x_end and not stats.left then stats.left = { t = model:time(), y = pos[2] } end
    local _, rule = model:dt()
    stats.rules[rule] = (stats.rules[rule] or 0) + 1
end)

-- ------------------------------------------------------------------ run

local clock = os.clock()
local t_max, why = 120, "time limit"
while m:time() < t_max do
    m:cycle(200)
    local pos, vel = rock.pos, rock.vel
    local speed = math.sqrt(vel[1] ^ 2 + vel[2] ^ 2)
    if stats.left then
        why = string.format("left the end of the profile (x = %g m) at t = %.2f s", x_end, stats.left.t)
        break
    end
    if stats.touching and speed < 0.02 and math.abs(rock.spin) * R < 0.02 then
        why = "came to rest"
        break
    end
end
local cpu = os.clock() - clock
history:close()

-- ------------------------------------------------------------------ summary

local pos = rock.pos
local e = m:energies()
local input = e.initial_kinetic + e.body + e.boundary
print(string.format("rockfall: rock R = %.2f m, m = %.0f kg; slope kn = %.3g N/m, Rn = %.2f "
    .. "(dp_nratio = %.3f), fric = 0.5, rolling friction %s", R, mass, kn, rn, beta,
    rolling and string.format("tan(beta) = %.2f (mu_r = %.2f)", tan_beta, mu_r) or "off"))
print(string.format("  stopped: %s; t = %.2f s after %d steps (%.2f s of CPU)", why, m:time(),
    m:step(), cpu))
local runout = stats.left and x_end or pos[1]
print(string.format("  final position (%.2f, %.2f) m, run-out x %s %.2f m", pos[1], pos[2],
    stats.left and ">" or "=", runout))
print(string.format("  impacts (normal speed > 0.5 m/s): %d of %d touches; highest bounce %.2f m "
    .. "above the slope (at x = %.1f m); peak speed %.1f m/s; deepest overlap %.3f m (%.0f%% of R)",
    #stats.impacts, stats.touches, stats.max_bounce, stats.max_bounce_x, stats.max_speed,
    stats.max_overlap, 100 * stats.max_overlap / R))
for k, imp in ipairs(stats.impacts) do
    if k <= 8 then
        print(string.format("    impact %d: t = %6.2f s, x = %6.2f m, normal speed %5.2f m/s", k,
            imp.t, imp.x, imp.vn))
    end
end
print(string.format("  energy [J]: input %.4g (body work %.4g), kinetic %.4g, slip %.4g, "
    .. "dashpot %.4g, strain %.4g", input, e.body, e.kinetic, e.slip, e.dashpot, e.strain))
print(string.format("  energy balance error %.3g J = %.2g of the input", e.balance_error,
    math.abs(e.balance_error) / input))
local names = {}
for name in pairs(stats.rules) do names[#names + 1] = name end
table.sort(names, function(a, b) return stats.rules[a] > stats.rules[b] end)
local parts = {}
for _, name in ipairs(names) do
    parts[#parts + 1] = string.format("%s %.1f%%", name, 100 * stats.rules[name] / m:step())
end
print("  time-step rule (share of steps): " .. table.concat(parts, ", "))
print("  last step: " .. m:timestep().reason)

-- Evans & Hungr (1993): rocks rarely travel beyond a 27.5 degree shadow line (B5). Measured
-- here from the crest of the profile (0, 60), the steepest reading of a stepped slope.
local crest = profile[1]
local reach = math.deg(math.atan(crest[2] - ground(runout), runout - crest[1]))
local bound = crest[1] + crest[2] / math.tan(math.rad(27.5))
print(string.format("  reach angle from the crest %.1f deg; the 27.5 deg shadow line ends at "
    .. "x = %.1f m: %s", reach, bound,
    reach >= 27.5 and "run-out within the empirical bound"
        or "run-out BEYOND the empirical bound (suspect: check rolling resistance and Rn)"))

-- ------------------------------------------------------------------ files for plots

-- The profile as a CSV with the history's x and y column names, so that one plot_history.py
-- command overlays the path of the rock on the slope. scripts/run_rockfall.sh draws both plots:
--   python3 scripts/plot_history.py out/rockfall_history.csv -o out/rockfall_history.png
--   python3 scripts/plot_history.py out/rockfall_history.csv out/rockfall_slope.csv \
--       -o out/rockfall_path.png --x x --columns y --equal
local slope_file = outdir .. "/rockfall_slope.csv"
local f = assert(io.open(slope_file, "w"))
f:write("x,y\n")
for _, p in ipairs(profile) do f:write(string.format("%.12g,%.12g\n", p[1], p[2])) end
assert(f:close())
print(string.format("  wrote %s/rockfall_history.csv and %s", outdir, slope_file))
