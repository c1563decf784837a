-- Headless Neovim test of snippet completion with `<C-x><C-o>`, set up as the README's "Neovim"
-- section says: the plugin with `require("gloc").setup({})`, then the README's `nvim-snippets`
-- block, read from README.md and run word for word. Before that block, `<C-x><C-o>` inserts a
-- mission argument's label (`wait_time`); with it, accepting the item expands the server's snippet
-- to `wait_time(sec) 720` (prepare_to_dive's default, from the simulator's argument table).
-- The keys are typed as a user types them (nvim_feedkeys), so Neovim's main loop must run: this
-- file is started with `-c luafile` (tests/e2e/run, nvim/interactive/), not `-l`, and ends itself.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -c "luafile tests/e2e/nvim/interactive/snippet_completion.lua"
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

vim.env.PATH = vim.fn.fnamemodify(H.gloc_bin, ":h") .. ":" .. vim.env.PATH
H.load_plugin_as_readme_says({})

--- The fenced block after `<!-- setup: NAME -->` in the README, as a reader copies it.
local function readme_block(name)
  local lines = vim.fn.readfile(H.repo .. "/README.md")
  local marker = "<!-- setup: " .. name .. " -->"
  for index, line in ipairs(lines) do
    if line == marker then
      local body = {}
      for at = index + 2, #lines do
        if lines[at]:match("^```") then
          return table.concat(body, "\n")
        end
        body[#body + 1] = lines[at]
      end
    end
  end
  error("no block " .. name .. " in README.md")
end

-- comet's mission with its .ma files, in a scratch project (two copies: one per phase).
local root = vim.fn.tempname()
vim.fn.mkdir(root .. "/missions", "p")
for _, name in ipairs({ "a.mi", "b.mi" }) do
  vim.fn.writefile(vim.fn.readfile(H.repo .. "/data/comet/missions/nsb3.mi"), root .. "/missions/" .. name)
end
vim.fn.system({ "cp", "-r", H.repo .. "/data/comet/mafiles", root .. "/" })

--- Opens the mission, types `b_arg: ` under prepare_to_dive (a line after its line 71), presses
--- `<C-x><C-o>` and, once the menu shows, `<C-n>` down to wait_time and `<C-y>`, then `<Esc>`;
--- calls `after` with the line.
local function complete_first_argument(file, after)
  local buffer = H.edit(root .. "/missions/" .. file)
  H.equal(vim.bo[buffer].filetype, "slocum_mission", file .. " is a mission")
  H.check(vim.wait(10000, function()
    local client = vim.lsp.get_clients({ bufnr = buffer, name = "gloc" })[1]
    return client ~= nil and client.initialized
  end, 50), "gloc lsp attaches to " .. file)
  vim.api.nvim_buf_set_lines(buffer, 71, 71, false, { "    b_arg: " })
  vim.api.nvim_win_set_cursor(0, { 72, 0 })
  local now = function() return vim.uv.hrtime() / 1e6 end
  local state, started, accepted, menu = "menu", now(), nil, false
  local timer
  timer = vim.fn.timer_start(50, function()
    if state == "menu" and vim.fn.pumvisible() == 1 then
      local info = vim.fn.complete_info({ "items", "selected" })
      local wanted
      for index, item in ipairs(info.items) do
        if item.abbr == "wait_time" or item.word == "wait_time" then wanted = index - 1 end
      end
      menu, state, accepted = wanted ~= nil, "accepted", now()
      local down = math.max((wanted or 0) - info.selected, 0)
      vim.api.nvim_feedkeys(vim.keycode(string.rep("<C-n>", down) .. "<C-y>"), "t", false)
    elseif (state == "accepted" and (vim.api.nvim_get_current_line():find("(", 1, true)
        or now() - accepted > 2000)) or (state == "menu" and now() - started > 10000) then
      state = "done"
      vim.fn.timer_stop(timer)
      vim.api.nvim_feedkeys(vim.keycode("<Esc>"), "t", false)
      vim.defer_fn(function()
        H.check(menu, "<C-x><C-o> shows a menu with wait_time in " .. file)
        local line = vim.api.nvim_buf_get_lines(buffer, 71, 72, false)[1]
        vim.bo[buffer].modified = false
        after(line)
      end, 300)
    end
  end, { ["repeat"] = -1 })
  vim.api.nvim_feedkeys(vim.keycode("A<C-x><C-o>"), "t", false)
end

-- Whatever happens, end.
vim.defer_fn(function()
  H.check(false, "the test finished within 60 s")
  H.finish()
end, 60000)

H.equal(vim.fn.readfile(H.repo .. "/data/comet/missions/nsb3.mi")[69], "behavior: prepare_to_dive",
  "line 69 of nsb3.mi opens prepare_to_dive")
-- Without the block: the label only.
complete_first_argument("a.mi", function(plain)
  H.equal(plain, "    b_arg: wait_time", "without the README's block: the label only")
  -- With it: the snippet, expanded.
  assert(loadstring(readme_block("nvim-snippets")))()
  complete_first_argument("b.mi", function(expanded)
    H.equal(expanded, "    b_arg: wait_time(sec) 720",
      "with the README's block: the snippet, expanded to the argument's units and default")
    H.finish()
  end)
end)
