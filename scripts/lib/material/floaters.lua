-- SPDX-License-Identifier: MIT
-- material/floaters.lua: where a floater goes (genesis step 3 of Potyondy & Cundall 2004,
-- "move/grow", docs/material.md): the circles tangent to three of its neighbours, and the
-- choice among them.
local F = {}

-- The circles tangent (externally) to three sites, in coordinates relative to the floater's
-- centre. A site is a ball {x, y, r}: |p - c| = rho + r, or a wall {nx, ny, w} (inward unit
-- normal n, line n.p = w): n.p - w = rho. Subtracting the first ball's equation from the other
-- balls' makes them linear in (x, y, rho); with the walls' equations that is two linear
-- equations, solved for x, y as affine functions of rho, and the first ball's equation becomes a
-- quadratic in rho (the Apollonius problem). Three walls: one 3 x 3 linear system.
-- Returns a list of {x, y, rho} with rho > 0.
function F.tangent_circles(a, b, c)
    local circ, lin = nil, {}
    for _, st in ipairs({ a, b, c }) do
        if st.w then
            lin[#lin + 1] = { st.nx, st.ny, -1, st.w }
        elseif not circ then
            circ = st
        else
            lin[#lin + 1] = { 2 * (circ.x - st.x), 2 * (circ.y - st.y), 2 * (circ.r - st.r),
                              circ.x * circ.x + circ.y * circ.y - circ.r * circ.r
                              - st.x * st.x - st.y * st.y + st.r * st.r }
        end
    end
    local out = {}
    if not circ then
        local e1, e2, e3 = lin[1], lin[2], lin[3]
        local function det3(c1, c2, c3)
            return c1[1] * (c2[2] * c3[3] - c2[3] * c3[2]) - c1[2] * (c2[1] * c3[3] - c2[3] * c3[1])
                + c1[3] * (c2[1] * c3[2] - c2[2] * c3[1])
        end
        local D = det3(e1, e2, e3)
        if math.abs(D) < 1e-12 then return out end
        local function col(k)
            local r1, r2, r3 = { e1[1], e1[2], e1[3] }, { e2[1], e2[2], e2[3] }, { e3[1], e3[2], e3[3] }
            r1[k], r2[k], r3[k] = e1[4], e2[4], e3[4]
            return det3(r1, r2, r3) / D
        end
        local rho = col(3)
        if rho > 0 then out[1] = { col(1), col(2), rho } end
        return out
    end
    local e1, e2 = lin[1], lin[2]
    local det = e1[1] * e2[2] - e1[2] * e2[1]
    local n1 = math.sqrt(e1[1] ^ 2 + e1[2] ^ 2)
    local n2 = math.sqrt(e2[1] ^ 2 + e2[2] ^ 2)
    if math.abs(det) <= 1e-9 * n1 * n2 then return out end -- parallel lines: no single point
    -- x = x0 + x1 rho, y = y0 + y1 rho (Cramer's rule on the 2 x 2 system in x, y)
    local x0 = (e1[4] * e2[2] - e1[2] * e2[4]) / det
    local y0 = (e1[1] * e2[4] - e1[4] * e2[1]) / det
    local x1 = (e1[2] * e2[3] - e1[3] * e2[2]) / det
    local y1 = (e1[3] * e2[1] - e1[1] * e2[3]) / det
    local ux, uy = x0 - circ.x, y0 - circ.y
    local A = x1 * x1 + y1 * y1 - 1
    local B = 2 * (ux * x1 + uy * y1) - 2 * circ.r
    local C = ux * ux + uy * uy - circ.r * circ.r
    local roots = {}
    if math.abs(A) < 1e-12 then
        if B ~= 0 then roots[1] = -C / B end
    else
        local disc = B * B - 4 * A * C
        if disc >= 0 then
            local q = -0.5 * (B + (B >= 0 and 1 or -1) * math.sqrt(disc)) -- no cancellation
            roots[1] = q / A
            if q ~= 0 then roots[2] = C / q end
        end
    end
    for _, rho in ipairs(roots) do
        if rho > 0 then out[#out + 1] = { x0 + x1 * rho, y0 + y1 * rho, rho } end
    end
    return out
end

--- The new place and size of a floater of radius R (genesis step 3, "move/grow"): among the
--- circles tangent to three of the K nearest sites (`sites` sorted by surface gap, relative to
--- the floater's centre; balls {x, y, r}, walls {nx, ny, w}), those that overlap no site (to
--- 1e-9 of their radius), whose centre lies within dmax, whose radius is in [R/2, 2R], and
--- whose three contact normals span the plane (no half-plane holds all three: the neighbours'
--- forces can hold the ball); of these the one with the smallest radius >= R (the floater grows
--- least), else the largest. `must` (optional): a set of site keys that the three must
--- include (the floater's current contact partners: a two-contact ball in a force chain keeps
--- its chain). Returns {x, y, rho} or nil.
function F.floater_circle(sites, R, dmax, K, must)
    K = math.min(K or 8, #sites)
    local nmust = 0
    for _ in pairs(must or {}) do nmust = nmust + 1 end
    local best_up, best_down
    for i = 1, K - 2 do
        for j = i + 1, K - 1 do
            for k = j + 1, K do
                local tri = { sites[i], sites[j], sites[k] }
                local has = 0
                for _, st in ipairs(tri) do
                    if must and st.key and must[st.key] then has = has + 1 end
                end
                if has < nmust then goto next_triple end
                for _, c in ipairs(F.tangent_circles(tri[1], tri[2], tri[3])) do
                    local x, y, rho = c[1], c[2], c[3]
                    local ok = rho >= 0.5 * R and rho <= 2 * R and x * x + y * y <= dmax * dmax
                    if ok then
                        for _, st in ipairs(sites) do
                            local gap
                            if st.w then gap = st.nx * x + st.ny * y - st.w - rho
                            else gap = math.sqrt((st.x - x) ^ 2 + (st.y - y) ^ 2) - st.r - rho end
                            if gap < -1e-9 * rho then ok = false; break end
                        end
                    end
                    if ok then
                        -- angles of the three contact normals; they span the plane when every
                        -- gap between consecutive angles is below pi
                        local ang = {}
                        for t, st in ipairs(tri) do
                            if st.w then ang[t] = math.atan(-st.ny, -st.nx)
                            else ang[t] = math.atan(st.y - y, st.x - x) end
                        end
                        table.sort(ang)
                        local gmax = math.max(ang[2] - ang[1], ang[3] - ang[2], ang[1] + 2 * math.pi - ang[3])
                        ok = gmax < math.pi
                    end
                    if ok then
                        if rho >= R then
                            if not best_up or rho < best_up[3] then best_up = c end
                        elseif not best_down or rho > best_down[3] then
                            best_down = c
                        end
                    end
                end
                ::next_triple::
            end
        end
    end
    return best_up or best_down
end

return F
