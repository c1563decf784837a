-- states.lua for LuaJIT (Lua 5.1 has no `//`: floor of the division instead), same work as states.gbas.
local t0 = os.clock()
local state, visits, turns = 0, 0, 0
for i = 1, 2000000 do
  if state == 0 then
    if i % 3 == 0 then
      state = 1
    else
      state = 2
    end
  elseif state == 1 then
    visits = visits + 1
    if i % 5 == 0 then
      state = 3
    end
  elseif state == 2 then
    if i % 7 < 3 then
      state = 0
    else
      state = 3
    end
  else
    turns = turns + 1
    state = math.floor((turns % 4) / 2)
  end
end
local t1 = os.clock()
print(state, visits, turns)
io.stderr:write(string.format("seconds %.9f\n", t1 - t0))
