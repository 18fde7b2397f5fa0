-- SPDX-License-Identifier: MIT
-- Stress-suite seeds 228, 684, 2266 and 2800 (docs/stress.md "Fixed"): energy created at
-- contacts whose shear spring is faster than the normal impact, and at a wall contact whose
-- spin lever arm changes within the step. Each scene is the stress generator's own (`talus run
-- tests/stress/stress.lua dump SEED`), run for the generator's 10 chunks; the balance error is
-- measured as the stress checker does (tests/stress/stress_check.lua): against the throughput,
-- the larger of the energy put in (initial kinetic + |body| + |boundary| work) and the peak
-- mechanical energy (kinetic + strain + bond), both maximised over the chunks.
local T = require("testlib")

local function run(build, chunk, chunks)
    local warnings = {}
    local m = build(warnings)
    local throughput, worst = 0, 0
    for _ = 1, chunks do
        m:cycle(chunk)
        local e = m:energies()
        local input = e.initial_kinetic + math.abs(e.body) + math.abs(e.boundary)
        throughput = math.max(throughput, input, e.kinetic + e.strain + e.bond)
        if math.abs(e.balance_error) > math.abs(worst) then worst = e.balance_error end
    end
    return worst / throughput, warnings
end

-- Seed 228: 18 disks in a V, no gravity, linear without dashpots, ks = 1.29 kn, fric 4.8. A
-- disk's shear inverse mass is 3x its normal one, so the sticking shear spring oscillates
-- sqrt(3 x 1.29) = 2x faster than the normal impact lasts: with linear's ContactDuration
-- following kn alone the resolution rule gave it 15 steps per half cycle, and impacts ended
-- with energy created at separation: -1.9% of the throughput (the stress checker printed
-- -0.95%: it counts the `input` total on top of its parts), -2.1% with the wall's lever-arm fix.
-- ContactDuration now takes the faster of the two springs: measured -0.67%, which falls with the
-- step as leapfrog's error does (-0.26% at resolution 60, -0.08% at 120). Bound: the suite's 1%.
do
    local rel, warnings = run(function(warnings)
    local m = talus.model{ gravity = {0, 0}, mass = "disk" }
    m:contact_model("linear", { dp_mode = 1, dp_nratio = 0, dp_sratio = 0, fric = 4.8074644180500519, kn = 49764.156267115053, ks = 64216.26957085124 })
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local W, B = {}, {}
    W[#W + 1] = m:wall{ points = {{-13.936750995106042, 16.370105349296811}, {-5.8776236653151503, 4.288650935115581}, {-5.5016861931906966, 4.3151586580777961}, {2.5574411366001959, 16.370105349296811}} }
    B[#B + 1] = m:ball{ density = 18783.759246177935, pos = {-3.8603583513123043, 8.1804753488799058}, radius = 0.42096560696924973, spin = 0.043658785357572651, vel = {0.010523605863772984, 0.018226395057616224} }
    B[#B + 1] = m:ball{ density = 243.66447459403585, pos = {-3.1785817979178379, 6.4698161904556351}, radius = 0.42096560696924973, vel = {0.031206617696103139, -0.012000152843573199} }
    B[#B + 1] = m:ball{ density = 2430.3824340716678, pos = {-7.6459871692332904, 11.312422167647625}, radius = 0.42096560696924973 }
    B[#B + 1] = m:ball{ density = 225.43786032180469, pos = {-6.8760683607410265, 10.580008589159037}, radius = 0.42096560696924973 }
    B[#B + 1] = m:ball{ density = 2052.6925778289319, pos = {-3.5047736944837311, 9.8659803869122662}, radius = 0.42096560696924973, spin = -0.024744572662185785, vel = {0.022210794164570207, 0.02088167715025583} }
    B[#B + 1] = m:ball{ mass = 158.66421969625964, pos = {-7.3699095814542783, 8.5954447814839838}, radius = 0.42096560696924973, vel = {0.021506969848366933, 0.017657880274619807} }
    B[#B + 1] = m:ball{ density = 149.14076482504396, pos = {-4.3311569833245818, 10.198441069440909}, radius = 0.42096560696924973, spin = -0.092257762600144261, vel = {0.00051409284787008269, 0.0053079269405201619} }
    B[#B + 1] = m:ball{ density = 210.3003249756311, pos = {-6.302978728466238, 7.1404545148589467}, radius = 0.42096560696924973, vel = {0.001620457768047399, -0.016563553404817487} }
    B[#B + 1] = m:ball{ density = 1898.3684898187248, pos = {-8.2985807866948207, 13.03079790880262}, radius = 0.42096560696924973, vel = {-0.00084782682155836841, -0.002740996326863717} }
    B[#B + 1] = m:ball{ density = 2433.8076471306445, pos = {-2.527844886441704, 12.991274213602267}, radius = 0.42096560696924973, spin = -0.058666814264102099, vel = {-0.036488305962311646, -0.0059894420717580294} }
    B[#B + 1] = m:ball{ density = 4554.9998203850746, pos = {-5.6566569038969483, 7.9276864915319916}, radius = 0.42096560696924973, vel = {-0.012872407396651539, -0.003160172777597562} }
    B[#B + 1] = m:ball{ density = 1940.011047349996, pos = {-2.7590472918853219, 11.749989966602943}, radius = 0.42096560696924973, vel = {-0.0082482779880316201, 0.0075065623369710557} }
    B[#B + 1] = m:ball{ density = 532.48143525612909, pos = {-9.3604872026219041, 5.3514661262863354}, radius = 0.42096560696924973, spin = 0.03542021362907815, vel = {0.0052689511897958735, -0.0016274931328170577} }
    B[#B + 1] = m:ball{ mass = 10252.361755825979, pos = {-3.3479409995018292, 8.9273603529767929}, radius = 0.42096560696924973, vel = {-0.011493058597935082, -0.035134457357636754} }
    B[#B + 1] = m:ball{ density = 10226.141904321752, pos = {-5.8849728788320714, 10.048618268037629}, radius = 0.42096560696924973, spin = -0.022494769211655618, vel = {-0.0042521376886030023, 0.0045157203798191856} }
    B[#B + 1] = m:ball{ density = 292.49289482391737, pos = {-2.4087578210175415, 10.4497215821188}, radius = 0.42096560696924973, spin = 0.056797164105013384, vel = {-0.020319289914076524, -0.0037181270081485178} }
    B[#B + 1] = m:ball{ density = 9869.5795255444009, pos = {-7.8348595534129366, 9.8248205284188153}, radius = 0.42096560696924973, spin = -0.027164828683596147, vel = {0.00036402982780312112, -0.0066806960817577974} }
    B[#B + 1] = m:ball{ density = 4939.9967507447218, pos = {-5.0676594669256056, 6.2743125999335767}, radius = 0.42096560696924973, vel = {0.016499909601114113, 0.0086264342557666376} }
    m:guard{ balance = "off" }
    m:energy{ on = true }
        return m
    end, 1000, 10)
    T.check(#warnings == 0, "seed 228: no warning (" .. tostring(warnings[1]) .. ")")
    T.check(math.abs(rel) < 0.01, string.format("seed 228: balance error %.3g%% of the throughput", 100 * rel))
    print(string.format("seed 228: balance error %.4f%% of the throughput", 100 * rel))
end

-- Seed 684: one disk sliding into the bottom of a V, linear with dashpots (dp_sratio 0.49,
-- dp_mode 0), ks = 25 kn: the shear spring is sqrt(3 x 25) = 8.7x faster than the normal
-- impact, 6 steps per half cycle with the step of the normal impact alone. Before: -2.94% of
-- the throughput (printed as -1.47%); measured now +0.047%. Bound 0.25%: 5x the measured
-- value, 12x below the old one.
do
    local rel, warnings = run(function(warnings)
    local m = talus.model{ gravity = {0, -9.8100000000000005}, mass = "disk" }
    m:contact_model("linear", { dp_mode = 0, dp_nratio = 0.54682585611410728, dp_sratio = 0.4857651559440529, fric = 1.8595865721218372, kn = 820884733.49184048, ks = 10482548.406303622 })
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local W, B = {}, {}
    W[#W + 1] = m:wall{ fric = 0.21899604361298156, kn = 423371.02196363895, points = {{-1.8689295166481541, 5.1418851693663079}, {-1.3980878936799046, 4.4437177320893335}, {-1.345118477221324, 4.4407456507884531}, {-0.87427685425307422, 5.1418851693663079}} }
    B[#B + 1] = m:ball{ density = 19753.191534132726, pos = {-1.2272592495290549, 4.8154821236022727}, radius = 0.080910316317702707 }
    m:guard{ balance = "off" }
    m:broadphase{ margin = 0.024075175453948071 }
    m:energy{ on = true }
        return m
    end, 1000, 10)
    T.check(#warnings == 0, "seed 684: no warning (" .. tostring(warnings[1]) .. ")")
    T.check(math.abs(rel) < 0.0025, string.format("seed 684: balance error %.3g%% of the throughput", 100 * rel))
    print(string.format("seed 684: balance error %.4f%% of the throughput", 100 * rel))
end

-- Seed 2266: one cbond ball bonded on touch in a V (soft: it sinks and breathes under its
-- weight while it rocks). The wall branch took the spin part of the shear rate with the lever
-- arm at the new overlap only; the half-step arm (as the ball-ball branch does) closes it.
-- Before: -2.65% of the throughput (created; printed as -1.33%); measured now +0.17% (lost).
-- Bound 0.5%: 3x the measured value, 5x below the old one.
do
    local rel, warnings = run(function(warnings)
    local m = talus.model{ gravity = {0, -9.8100000000000005}, mass = "disk" }
    m:contact_model("cbond", { cb_bond = 1, cb_gap = 1.2122274541568048e-05, cb_shearf = math.huge, cb_tenf = math.huge, fric = 0, kn = 2463743.3432581099, ks = 692311.65834306006 })
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local W, B = {}, {}
    W[#W + 1] = m:wall{ points = {{5.7269711387131723, -3.8358800367477861}, {6.4553644094237725, -4.9368732107432116}, {6.5413103693853696, -4.9538014052349899}, {7.2697036400959698, -3.8358800367477861}} }
    B[#B + 1] = m:ball{ mass = 786.00978380940001, pos = {6.5320606746548906, -4.3033146881683022}, radius = 0.26714780897227614, vel = {0.29497529568902048, 0.18270270157374313} }
    m:guard{ balance = "off" }
    m:broadphase{ margin = 0.041580052753099402 }
    m:energy{ on = true }
        return m
    end, 1000, 10)
    T.check(#warnings == 0, "seed 2266: no warning (" .. tostring(warnings[1]) .. ")")
    T.check(math.abs(rel) < 0.005, string.format("seed 2266: balance error %.3g%% of the throughput", 100 * rel))
    print(string.format("seed 2266: balance error %.4f%% of the throughput", 100 * rel))
end

-- Seed 2800: three clumps in a box, cbond bonding on touch with a very stiff normal spring
-- (kn 1.1e11 N/m, cb_tenf 370 N: the tensile range is 3e-9 m) and resolution 10. Every impact's
-- bond breaks in tension in the step the spring crosses zero: F_old F_trial / 2k booked a
-- negative release (-462 J) and the balance lost 10.2% of the throughput (-1.0% at resolution
-- 30; the same scene with `linear`: -0.06% and +0.008%). The crossing is now a separation with
-- its closing corner, and a bond made at touch gets the onset corner: the scene then runs
-- as `linear` does; measured -0.067%. Bound 0.5%: 7x the measured value, 20x below the old.
do
    local rel, warnings = run(function(warnings)
    local m = talus.model{ gravity = {0, -9.8100000000000005}, mass = "disk" }
    m:contact_model("cbond", { cb_bond = 1, cb_gap = 0, cb_shearf = 4.0204496446584361, cb_tenf = 370.52395533400221, fric = 2.4216539851664782, kn = 111888489059.43462, ks = 0 })
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local W, B = {}, {}
    W[#W + 1] = m:wall{ closed = true, points = {{5.5934982652690177, -5.8653471568396842}, {7.3476887473608397, -5.8653471568396842}, {7.3476887473608397, -4.254023817718144}, {5.5934982652690177, -4.254023817718144}} }
    B[#B + 1] = m:clump{ angle = 2.4917493786984126, density = 624.70217667197301, pebbles = {{0.062915009175197129, 0.010810361804237093, 0.053875165411853748}, {0.083243889320166589, 0.039967245128921677, 0.046521995915545303}}, pos = {6.638015662525321, -5.1361356550506727}, spin = 22.689558159811053, vel = {3.1047906398871974, -3.4480164939294102} }
    B[#B + 1] = m:clump{ angle = 0.48315923429586016, density = 405.47293916941169, mass_mode = "union", pebbles = {{0.0019420386508886402, -0.012052379663600924, 0.069808038430042005}}, pos = {6.2175523681500318, -5.4010791121290067}, scale = 0.97631896749375779, vel = {2.5097088576576017, -8.302658313930845} }
    B[#B + 1] = m:clump{ density = 3587.750281652246, pebbles = {{-0.008122669431939053, 0.021215551605776945, 0.053084908897400467}, {-0.015695555139075008, 0.00024471108444456765, 0.048633165386357119}, {-0.0027954032831728399, -0.013892320474137002, 0.031228710448139258}}, pos = {6.9972621996288362, -4.7078222105811305}, scale = 0.74906882237811589, vel = {-17.492503298447872, 8.0514691698203382} }
    m:timestep{ growth = 2.605443705070325, resolution = 10, safety = 0.39127895739759155 }
    m:guard{ balance = "off" }
    m:energy{ on = true }
        return m
    end, 1000, 10)
    T.check(#warnings == 0, "seed 2800: no warning (" .. tostring(warnings[1]) .. ")")
    T.check(math.abs(rel) < 0.005, string.format("seed 2800: balance error %.3g%% of the throughput", 100 * rel))
    print(string.format("seed 2800: balance error %.4f%% of the throughput", 100 * rel))
end

-- Seed 1440 (seven-model generator): `ng`, one ball in a valley, PFC local damping 0.88 and an
-- applied 170 N against a start velocity of 4 mm/s. The damping force (sign of the old
-- velocity) pushes along the load for the whole first step (0.023 s, the free ball's automatic
-- step) while the velocity reverses inside it; booked on the mean of the half-step velocities,
-- the first cycle's half window lost 0.47 J = 1.65% of the throughput before any contact. Local
-- damping is now booked on the velocity at t (docs/physics/energy.md): measured 0.015%, from the
-- contacts. Bound 0.1%: 7x the measured value, 16x below the old.
do
    local rel, warnings = run(function(warnings)
    local m = talus.model{ gravity = {0, -9.8100000000000005}, mass = "disk" }
    m:contact_model("ng", { fric = 0.054418587829915953, ng_form = 0, ng_poiss = 0.25033278378329143, ng_shear = 603504715.26540446 })
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local W, B = {}, {}
    W[#W + 1] = m:wall{ points = {{0.50581857136224173, -1.3593610261098694}, {0.70529034829266202, -1.957342716945542}, {0.72674360916964509, -1.9529656825873045}, {0.92621538610006537, -1.3593610261098694}} }
    B[#B + 1] = m:ball{ density = 530.75759330143899, pos = {0.70883978122859836, -1.5211585892124899}, radius = 0.091599545038365246, vel = {0.0038515980548484209, 0.0073476814408325094} }; B[#B].fapp = {-170.03779375017356, -28.390650066029753}
    m:damping{ ["local"] = 0.88079027083900785 }
    m:timestep{ growth = 1.8234919586660707, resolution = 30, safety = 0.8674404998971097 }
    m:guard{ balance = "off" }
    m:energy{ on = true }
        return m
    end, 1000, 10)
    T.check(#warnings == 0, "seed 1440: no warning (" .. tostring(warnings[1]) .. ")")
    T.check(math.abs(rel) < 0.001, string.format("seed 1440: balance error %.3g%% of the throughput", 100 * rel))
    print(string.format("seed 1440: balance error %.4f%% of the throughput", 100 * rel))
end

print("stress_seeds_energy: " .. T.checks .. " checks passed")
