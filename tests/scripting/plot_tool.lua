-- SPDX-License-Identifier: MIT
-- plot_csv as a module: blank/NaN cells leave gaps, legend, axes, deterministic output.
local T = require("testlib")
local plot_csv = require("plot_csv")
local dir = arg[1] or "."

local csv = dir .. "/plot_input.csv"
local f = assert(io.open(csv, "w"))
f:write('time,"energy, kinetic",slip\n')
f:write("0,1,0\n0.1,2,\n0.2,nan,0.5\n\n0.3,4,0.75\n0.4,5,1\n0.5,,1.25\n0.6,7,inf\n")
f:close()

local t = plot_csv.read(csv)
T.check(#t.header == 3 and t.header[2] == "energy, kinetic", "quoted header cell")
T.check(t.rows == 7, "blank lines are skipped")
T.check(t.columns.slip[2] ~= t.columns.slip[2], "blank cell -> NaN")
T.check(t.columns["energy, kinetic"][3] ~= t.columns["energy, kinetic"][3], "nan -> NaN")

local svg = dir .. "/plot_output.svg"
plot_csv.plot{ input = csv, output = svg, title = "test <plot>" }
local text = assert(io.open(svg)):read("a")
T.check(text:find("^<svg"), "an SVG document")
T.check(text:find("test &lt;plot&gt;", 1, true), "title escaped")
T.check(text:find(">energy, kinetic</text>", 1, true) and text:find(">slip</text>", 1, true),
    "legend names")
local polylines = select(2, text:gsub("<polyline", ""))
-- kinetic: (0,1)(0.1,2) | (0.3..0.4) | (0.6) -> 2 polylines + 1 dot; slip: (0) | (0.2..0.5) -> 1 + dot
T.check(polylines == 3, "gaps split the lines (" .. polylines .. " polylines)")
T.check(select(2, text:gsub("<circle", "")) == 2, "isolated points are dots")
T.check(text:find(">time</text>", 1, true), "x label from the column name")

plot_csv.plot{ input = csv, output = dir .. "/plot_output2.svg", title = "test <plot>" }
T.check(assert(io.open(dir .. "/plot_output2.svg")):read("a") == text, "deterministic output")

plot_csv.plot{ input = csv, output = dir .. "/plot_output3.svg", x = 1, y = { "slip" }, equal = true,
               extra = { { name = "line", x = { 0, 1 }, y = { 0, 1 } } } }
T.fails(function() plot_csv.plot{ input = csv, output = svg, y = { "nope" } } end,
    { "plot_csv: no y column 'nope' (columns: time, energy, kinetic, slip)" }, "unknown column")
T.done("plot_csv")
