-- Thermocline bin averaging over arrays (benchmark 2 of 3), same work as bins.gbas.
-- Arrays are 0-based like GBASIC's (Lua tables accept index 0).
local t0 = os.clock()
local nbins = 50
local sum, count, avg, deriv = {}, {}, {}, {}
for b = 0, nbins - 1 do sum[b] = 0.0; count[b] = 0; avg[b] = 0.0; deriv[b] = 0.0 end
local mean, acc = 0.0, 0
for rep = 1, 2000 do
  for b = 0, nbins - 1 do
    sum[b] = 0.0
    count[b] = 0
  end
  for k = 0, 399 do
    local z = (k % 50) + 0.25
    local b = math.floor(z)
    local temp = 20.0 - 0.05 * z
    if z > 10.0 and z < 15.0 then
      temp = temp - (z - 10.0)
    elseif z >= 15.0 then
      temp = temp - 5.0
    end
    sum[b] = sum[b] + temp
    count[b] = count[b] + 1
  end
  for b = 0, nbins - 1 do
    if count[b] > 0 then
      avg[b] = sum[b] / count[b]
    end
  end
  mean = 0.0
  for b = 1, nbins - 1 do
    deriv[b] = math.abs(avg[b] - avg[b - 1])
    mean = mean + deriv[b]
  end
  mean = mean / (nbins - 1)
  local upper, lower = -1, -1
  for b = 1, nbins - 1 do
    if deriv[b] > mean then
      if upper < 0 then upper = b end
      lower = b
    end
  end
  acc = acc + upper + lower
end
local t1 = os.clock()
print(acc, string.format("%.17g", mean))
io.stderr:write(string.format("seconds %.9f\n", t1 - t0))
