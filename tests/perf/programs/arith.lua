-- Tight integer and float arithmetic loop (benchmark 1 of 3), same work as arith.gbas.
local t0 = os.clock()
local acc = 0
local x = 0.0
for i = 1, 3000000 do
  acc = (acc + i * 7) % 1000003
  x = x * 0.5 + (i % 10)
end
local t1 = os.clock()
print(acc, string.format("%.17g", x))
io.stderr:write(string.format("seconds %.9f\n", t1 - t0))
