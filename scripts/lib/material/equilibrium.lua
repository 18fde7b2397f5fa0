-- SPDX-License-Identifier: MIT
-- material/equilibrium.lua: a model set up for quasi-static work, its step held at the
-- automatic step, and relaxation to PFC's unbalanced-force ratio (mean unbalanced force over
-- balls / mean contact force, m:unbalanced).
local E = {}

--- A model for quasi-static work: the stability rule alone sets the step (the resolution rule
--- is for impacts, docs/models/cbond.md "Time-step contract"), PFC local damping (Potyondy &
--- Cundall 2004: 0.7) and the impact guards off (no impacts are resolved here). The engine's
--- warnings are printed: a routine that overlaps bodies on purpose switches that warning off
--- itself (m:placement_warning(false)) and says so.
function E.new_model(damp)
    local m = talus.model{}
    m:timestep{ resolution = 0 }
    m:damping{ damp = damp or 0.7 }
    m:guard{ energy = "off", resolution = "off" }
    return m
end

function E.unbalanced_ratio(m) return m:unbalanced().ratio end

--- Holds the step at the automatic step of now: two cycles with the automatic step (the first
--- may use the stiffness sums of an older cycle; the second has this one's), then that step
--- fixed. A fixed step skips the automatic rule's work in every cycle (the stability rule's
--- pass over the bodies and the limits the force loop gathers per pair: about a fifth of a step
--- of a bonded specimen, docs/material.md). Safe for a dense quasi-static scene re-held often
--- enough: the stability rule's step, 0.8 sqrt(m / k) with k the sum of a body's contact
--- stiffnesses, is below the central-difference limit sqrt(2 m / k) of the stiffest body by a
--- factor 1.77, so a body may stiffen by 3.1 times before the held step is unstable; a disk
--- among disks of radii within a factor 1.66 has at most 6-7 contacts. Returns the step.
function E.hold_step(m)
    m:timestep{ fixed = false }
    m:cycle(2)
    local dt = m:dt()
    m:timestep{ fixed = dt }
    return dt
end

--- Cycles with the step held (E.hold_step) and held again every `every` steps (a number, or a
--- function giving it when asked; nil: the automatic step throughout). Returns a stepper:
--- cycle(n) runs n steps, the hold's two automatic ones among them; release() makes the step
--- automatic again if it was held.
function E.held_stepper(m, every)
    local held_at = nil
    local st = {}
    local function due()
        return not held_at or m:step() - held_at >= (type(every) == "function" and every() or every)
    end
    function st.cycle(n)
        if every and n > 2 and due() then
            held_at = m:step()
            E.hold_step(m)
            n = n - 2
        end
        m:cycle(n)
    end
    function st.release()
        if held_at then m:timestep{ fixed = false } end
    end
    return st
end

--- A relaxation has stalled when its ratio has not fallen below stall_drop (0.9) of its best
--- for a window of steps (docs/material.md "Genesis").
E.stall_drop = 0.9

--- Cycles until the ratio is at most `ratio` (or max_steps). Returns the steps taken, the final
--- ratio and why it stopped: "ratio"; "stalled" (with `window`: the ratio has not fallen below
--- 0.9 of its best for the last `window` steps, so more cycling only follows the packing's slow
--- creep); "max_steps" (a cap); or "no_contacts" (no contact carries a force: nothing to
--- settle, the ratio is undefined). Without `chunk`: m:solve{ratio}, judged after every step.
--- With `chunk` the ratio is judged every `chunk` steps (m:cycle, then m:unbalanced()): the
--- per-step pass over balls and pairs is ~25% of a genesis step at 5000 balls (docs/lua-api.md),
--- and a relaxation may overrun by < chunk steps. `hold` (with chunk): the step is held
--- (E.hold_step) at the start and re-held every `hold` steps, and automatic again at the end.
function E.solve_ratio(m, ratio, max_steps, chunk, window, hold)
    local s0 = m:step()
    if not chunk then
        m:solve{ ratio = ratio, max_steps = max_steps }
        local r = m:unbalanced().ratio
        return m:step() - s0, r, r <= ratio and "ratio" or "max_steps"
    end
    local r = math.huge
    local best, best_at = math.huge, 0
    local stepper = E.held_stepper(m, hold)
    local function done(why)
        stepper.release()
        return m:step() - s0, r, why
    end
    while m:step() - s0 < max_steps do
        stepper.cycle(math.min(chunk, max_steps - (m:step() - s0)))
        local u = m:unbalanced()
        r = u.ratio
        local k = m:step() - s0
        if u.contacts == 0 then return done("no_contacts") end
        if r <= ratio then return done("ratio") end
        if r <= E.stall_drop * best then best, best_at = r, k end
        if window and k - best_at >= window then return done("stalled") end
    end
    return done("max_steps")
end

return E
