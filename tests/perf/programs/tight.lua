-- A tight integer loop (benchmark 4 of 4), same work as tight.gbas.
local t0 = os.clock()
local s = 0
for i = 1, 5000000 do
  s = s + (i * i) % 7
end
local t1 = os.clock()
print(s)
io.stderr:write(string.format("seconds %.9f\n", t1 - t0))
