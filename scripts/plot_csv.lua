-- SPDX-License-Identifier: MIT
--
-- plot_csv: a dependency-free CSV -> SVG line plot (energy histories, trajectories).
--
-- As a command:
--   talus run scripts/plot_csv.lua in.csv out.svg [xcol] [ycol ...] [--title=T] [--equal]
--                                  [--xlabel=X] [--ylabel=Y] [--width=W] [--height=H]
--   xcol defaults to the first column, the y columns to all the others. Columns are named by
--   header or by 1-based number. --equal gives both axes the same scale (trajectories).
--
-- As a module (one command can simulate and plot):
--   local plot_csv = require("plot_csv")
--   plot_csv.plot{ input = "out/h.csv", output = "out/h.svg", x = "time",
--                  y = {"kinetic", "slip"}, title = "...", equal = false,
--                  extra = { {name = "slope", x = {...}, y = {...}} } }   -- more polylines
--   local t = plot_csv.read("out/h.csv")   -- {header = {...}, columns = {name = {...}}, rows = n}
--
-- Blank, non-numeric, NaN and infinite cells leave a gap in the line; they never stop the plot.
-- Output is deterministic (fixed number formats, no dates).

local M = {}

local NAN = 0 / 0
local function isnan(v) return v ~= v end
local function finite(v) return v == v and v ~= math.huge and v ~= -math.huge end

local PALETTE = {
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
}

-- ------------------------------------------------------------------ CSV

-- Splits one CSV line into cells (RFC 4180 quotes; no embedded line breaks).
local function split_line(line)
    local cells, i, n = {}, 1, #line
    while i <= n + 1 do
        if line:sub(i, i) == '"' then
            local value, j = {}, i + 1
            while j <= n do
                local c = line:sub(j, j)
                if c == '"' then
                    if line:sub(j + 1, j + 1) == '"' then
                        value[#value + 1] = '"'
                        j = j + 2
                    else
                        j = j + 1
                        break
                    end
                else
                    value[#value + 1] = c
                    j = j + 1
                end
            end
            cells[#cells + 1] = table.concat(value)
            local comma = line:find(",", j, true)
            i = comma and comma + 1 or n + 2
        else
            local comma = line:find(",", i, true)
            if comma then
                cells[#cells + 1] = line:sub(i, comma - 1)
                i = comma + 1
            else
                cells[#cells + 1] = line:sub(i)
                i = n + 2
            end
        end
    end
    return cells
end

local function trim(s) return (s:gsub("^%s+", ""):gsub("%s+$", "")) end

--- Reads a CSV file with a header row. Cells that are not finite numbers become NaN.
function M.read(path)
    local f, err = io.open(path, "r")
    if not f then error("plot_csv: cannot read '" .. path .. "' (" .. tostring(err) .. ")", 2) end
    local header, columns, rows = nil, {}, 0
    for line in f:lines() do
        line = line:gsub("\r$", "")
        if not header then
            if trim(line) ~= "" then
                header = split_line(line)
                for k, name in ipairs(header) do
                    header[k] = trim(name)
                    columns[header[k]] = {}
                end
            end
        elseif trim(line) ~= "" then
            rows = rows + 1
            local cells = split_line(line)
            for k, name in ipairs(header) do
                local v = tonumber(trim(cells[k] or ""))
                if v == nil or not finite(v) then v = NAN end
                columns[name][rows] = v
            end
        end
    end
    f:close()
    if not header then error("plot_csv: '" .. path .. "' is empty (no header row)", 2) end
    return { header = header, columns = columns, rows = rows }
end

-- ------------------------------------------------------------------ axes

-- A "nice" step (1, 2, 2.5 or 5 times a power of ten) near range / count.
local function nice_step(range, count)
    local raw = range / count
    local mag = 10 ^ math.floor(math.log(raw, 10))
    for _, m in ipairs({ 1, 2, 2.5, 5, 10 }) do
        if raw <= m * mag * (1 + 1e-9) then return m * mag end
    end
    return 10 * mag
end

-- Axis limits widened to whole ticks, and the ticks.
local function axis(lo, hi, count)
    if not (lo and hi) or not finite(lo) or not finite(hi) then lo, hi = 0, 1 end
    if hi - lo <= math.abs(hi) * 1e-12 then
        local pad = (lo == 0) and 1 or math.abs(lo) * 0.1
        lo, hi = lo - pad, hi + pad
    end
    local step = nice_step(hi - lo, count)
    local first = math.floor(lo / step + 1e-9) * step
    local last = math.ceil(hi / step - 1e-9) * step
    local ticks = {}
    local k = 0
    while true do
        local t = first + k * step
        if t > last + step * 1e-9 then break end
        if math.abs(t) < step * 1e-9 then t = 0 end
        ticks[#ticks + 1] = t
        k = k + 1
    end
    return first, last, ticks, step
end

local function tick_label(v, step)
    local a = math.max(math.abs(v), step)
    if a >= 1e5 or step < 1e-3 then
        local s = string.format("%.3g", v)
        return s
    end
    local decimals = math.max(0, -math.floor(math.log(step, 10) + 1e-9))
    if step * 10 ^ decimals % 1 > 1e-6 then decimals = decimals + 1 end  -- steps of 2.5
    return string.format("%." .. decimals .. "f", v)
end

local function escape(s)
    return (tostring(s):gsub("&", "&amp;"):gsub("<", "&lt;"):gsub(">", "&gt;"):gsub('"', "&quot;"))
end

local function column_of(t, spec, what)
    local n = tonumber(spec)
    local name = spec
    if n and math.type(n) == "integer" and t.header[n] then name = t.header[n] end
    if not t.columns[name] then
        error(string.format("plot_csv: no %s column '%s' (columns: %s)", what, tostring(spec),
            table.concat(t.header, ", ")), 3)
    end
    return name, t.columns[name]
end

-- ------------------------------------------------------------------ SVG

--- Plots columns of a CSV file (or of a table from M.read) into an SVG file.
function M.plot(opts)
    assert(type(opts) == "table", "plot_csv.plot{input =, output =, ...}")
    local t = opts.data or M.read(assert(opts.input, "plot_csv.plot: 'input' is required"))
    local output = assert(opts.output, "plot_csv.plot: 'output' is required")
    local width, height = opts.width or 800, opts.height or 500

    local xname, xs = column_of(t, opts.x or 1, "x")
    local ynames = opts.y
    if type(ynames) == "string" then ynames = { ynames } end
    if not ynames or #ynames == 0 then
        ynames = {}
        for _, name in ipairs(t.header) do
            if name ~= xname then ynames[#ynames + 1] = name end
        end
    end
    local series = {}
    for k, spec in ipairs(ynames) do
        local name, ys = column_of(t, spec, "y")
        series[#series + 1] = { name = name, x = xs, y = ys, color = PALETTE[(k - 1) % #PALETTE + 1] }
    end
    for _, e in ipairs(opts.extra or {}) do
        series[#series + 1] = { name = e.name or "", x = e.x, y = e.y, color = e.color or "#555555",
                                dash = e.dash }
    end
    if #series == 0 then error("plot_csv: nothing to plot (no y columns)", 2) end

    -- Data limits over every finite point.
    local xlo, xhi, ylo, yhi
    for _, s in ipairs(series) do
        for i = 1, math.min(#s.x, #s.y) do
            local x, y = s.x[i], s.y[i]
            if finite(x) and finite(y) then
                xlo = xlo and math.min(xlo, x) or x
                xhi = xhi and math.max(xhi, x) or x
                ylo = ylo and math.min(ylo, y) or y
                yhi = yhi and math.max(yhi, y) or y
            end
        end
    end

    local left, right, top, bottom = 90, 30, 50, 60
    local pw, ph = width - left - right, height - top - bottom
    if opts.equal and xlo and ylo then
        -- Same metres per pixel on both axes: widen the shorter range around its centre.
        local sx, sy = (xhi - xlo) / pw, (yhi - ylo) / ph
        if sx > sy then
            local c, half = (ylo + yhi) / 2, sx * ph / 2
            ylo, yhi = c - half, c + half
        else
            local c, half = (xlo + xhi) / 2, sy * pw / 2
            xlo, xhi = c - half, c + half
        end
    end
    local x0, x1, xticks, xstep = axis(xlo, xhi, 8)
    local y0, y1, yticks, ystep = axis(ylo, yhi, 6)
    if opts.equal then
        -- Keep the equal scale after rounding to ticks: the plot box takes the data's shape.
        local scale = math.max((x1 - x0) / pw, (y1 - y0) / ph)
        pw, ph = (x1 - x0) / scale, (y1 - y0) / scale
        width, height = math.ceil(left + pw + right), math.ceil(top + ph + bottom)
    end
    local function px(x) return left + (x - x0) / (x1 - x0) * pw end
    local function py(y) return top + ph - (y - y0) / (y1 - y0) * ph end

    local out = {}
    local function w(...) out[#out + 1] = string.format(...) end
    w('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
        .. 'font-family="sans-serif" font-size="12">\n', width, height, width, height)
    w('<rect width="%d" height="%d" fill="white"/>\n', width, height)
    w('<text x="%.1f" y="25" text-anchor="middle" font-size="15">%s</text>\n', left + pw / 2,
        escape(opts.title or opts.input or ""))

    -- grid, ticks and tick labels
    w('<g stroke="#e5e5e5" stroke-width="1">\n')
    for _, v in ipairs(xticks) do w('<line x1="%.2f" y1="%.2f" x2="%.2f" y2="%.2f"/>\n', px(v), top, px(v), top + ph) end
    for _, v in ipairs(yticks) do w('<line x1="%.2f" y1="%.2f" x2="%.2f" y2="%.2f"/>\n', left, py(v), left + pw, py(v)) end
    w('</g>\n<g stroke="black" stroke-width="1">\n')
    for _, v in ipairs(xticks) do w('<line x1="%.2f" y1="%.2f" x2="%.2f" y2="%.2f"/>\n', px(v), top + ph, px(v), top + ph + 5) end
    for _, v in ipairs(yticks) do w('<line x1="%.2f" y1="%.2f" x2="%.2f" y2="%.2f"/>\n', left - 5, py(v), left, py(v)) end
    w('</g>\n<rect x="%d" y="%d" width="%.2f" height="%.2f" fill="none" stroke="black"/>\n', left, top, pw, ph)
    w('<g text-anchor="middle">\n')
    for _, v in ipairs(xticks) do w('<text x="%.2f" y="%.2f">%s</text>\n', px(v), top + ph + 20, tick_label(v, xstep)) end
    w('</g>\n<g text-anchor="end">\n')
    for _, v in ipairs(yticks) do w('<text x="%.2f" y="%.2f">%s</text>\n', left - 8, py(v) + 4, tick_label(v, ystep)) end
    w('</g>\n')
    w('<text x="%.2f" y="%.2f" text-anchor="middle">%s</text>\n', left + pw / 2, top + ph + 45,
        escape(opts.xlabel or xname))
    local ylabel = opts.ylabel or (#ynames == 1 and series[1].name or "")
    w('<text x="20" y="%.2f" text-anchor="middle" transform="rotate(-90 20 %.2f)">%s</text>\n',
        top + ph / 2, top + ph / 2, escape(ylabel))

    -- one polyline per run of finite points; points on the same half pixel are merged
    w('<g fill="none" stroke-width="1.5" stroke-linejoin="round">\n')
    for _, s in ipairs(series) do
        local dash = s.dash and string.format(' stroke-dasharray="%s"', s.dash) or ""
        local pts, lastx, lasty = {}, nil, nil
        local function flush()
            if #pts >= 2 then
                w('<polyline stroke="%s"%s points="%s"/>\n', s.color, dash, table.concat(pts, " "))
            elseif #pts == 1 then
                local x, y = pts[1]:match("([^,]+),([^,]+)")
                w('<circle cx="%s" cy="%s" r="2" fill="%s" stroke="none"/>\n', x, y, s.color)
            end
            pts, lastx, lasty = {}, nil, nil
        end
        for i = 1, math.min(#s.x, #s.y) do
            local x, y = s.x[i], s.y[i]
            if finite(x) and finite(y) then
                local qx, qy = math.floor(px(x) * 2 + 0.5) / 2, math.floor(py(y) * 2 + 0.5) / 2
                if qx ~= lastx or qy ~= lasty then
                    pts[#pts + 1] = string.format("%.1f,%.1f", qx, qy)
                    lastx, lasty = qx, qy
                end
            else
                flush()
            end
        end
        flush()
    end
    w('</g>\n')

    -- legend (top right, inside the plot)
    local named = {}
    for _, s in ipairs(series) do if s.name ~= "" then named[#named + 1] = s end end
    if #named > 1 or (#named == 1 and #ynames > 1) or (opts.extra and #named > 0) then
        local longest = 0
        for _, s in ipairs(named) do longest = math.max(longest, #s.name) end
        local lw, lh = 40 + 7 * longest, 8 + 18 * #named
        local lx, ly = left + pw - lw - 8, top + 8
        w('<g>\n<rect x="%.2f" y="%.2f" width="%.2f" height="%.2f" fill="white" fill-opacity="0.85" stroke="#999"/>\n',
            lx, ly, lw, lh)
        for k, s in ipairs(named) do
            local yk = ly + 4 + 18 * (k - 0.5)
            local dash = s.dash and string.format(' stroke-dasharray="%s"', s.dash) or ""
            w('<line x1="%.2f" y1="%.2f" x2="%.2f" y2="%.2f" stroke="%s" stroke-width="2"%s/>\n',
                lx + 6, yk, lx + 30, yk, s.color, dash)
            w('<text x="%.2f" y="%.2f">%s</text>\n', lx + 36, yk + 4, escape(s.name))
        end
        w('</g>\n')
    end
    w('</svg>\n')

    local f, err = io.open(output, "w")
    if not f then error("plot_csv: cannot write '" .. output .. "' (" .. tostring(err) .. ")", 2) end
    f:write(table.concat(out))
    f:close()
    return output
end

-- ------------------------------------------------------------------ command line

local function main(args)
    local positional, opts = {}, {}
    for _, a in ipairs(args) do
        local key, value = a:match("^%-%-([%w_]+)=(.*)$")
        if key then
            opts[key] = value
        elseif a == "--equal" then
            opts.equal = true
        elseif a:match("^%-%-") then
            error("plot_csv: unknown option '" .. a .. "'", 0)
        else
            positional[#positional + 1] = a
        end
    end
    if #positional < 2 then
        io.stderr:write("usage: talus run plot_csv.lua in.csv out.svg [xcol] [ycol ...] "
            .. "[--title=T] [--equal] [--xlabel=X] [--ylabel=Y] [--width=W] [--height=H]\n")
        os.exit(2)
    end
    local ys = {}
    for k = 4, #positional do ys[#ys + 1] = positional[k] end
    M.plot{
        input = positional[1], output = positional[2], x = positional[3], y = ys,
        title = opts.title, xlabel = opts.xlabel, ylabel = opts.ylabel, equal = opts.equal,
        width = tonumber(opts.width), height = tonumber(opts.height),
    }
    print("plot_csv: wrote " .. positional[2])
end

-- Run as a command when this file is the script (`...` are its arguments); when loaded with
-- require, `...` is the module name and the file only returns the module.
if arg and arg[0] and arg[0]:match("plot_csv%.lua$") and (...) ~= "plot_csv" then
    main({ ... })
end

return M
