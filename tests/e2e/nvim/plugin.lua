-- Headless Neovim test of the editors/nvim plugin without the language server: filetype
-- detection, syntax groups, buffer settings, indentation and the nvim-dap configuration.
-- Run: nvim --headless -u NONE -l tests/e2e/nvim/plugin.lua   (tests/e2e/run does this)
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

H.check(vim.fn.has("nvim-0.11") == 1, "Neovim is 0.11 or later", vim.version())
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin })

local dir = vim.fn.tempname()
local gbas_path = dir .. "/fig3.gbas"
local gloc_path = dir .. "/fig2.gloc"
local gbas_lines = vim.list_extend(vim.deepcopy(H.fig3), {
  "' a comment with goto and 15.0",
  "dim depths(10) as float",
  "x = float(n) + abs(c_pitch) ' trailing",
  "rem the rest is a comment",
  "print \"it's \"\"fine\"\"\", sci_water_temp",
})
H.write_file(gbas_path, gbas_lines)
H.write_file(gloc_path, vim.list_extend(vim.deepcopy(H.fig2), { "prints \"depth # now\" # a comment" }))

-- GBASIC ---------------------------------------------------------------------------------------
local gbas = H.edit(gbas_path)
H.equal(vim.bo[gbas].filetype, "gbasic", ".gbas has filetype gbasic")
H.equal(vim.b[gbas].current_syntax, "gbasic", "syntax/gbasic.vim is loaded")
H.equal(vim.bo[gbas].commentstring, "' %s", "GBASIC commentstring is ' %s")

local function expect_syntax(line, column, group, linked)
  local name, final = H.syntax_at(line, column)
  H.equal({ name, final }, { group, linked }, ("%s at %d:%d"):format(group, line, column))
end

expect_syntax(1, 1, "gbasicLabelKeyword", "Label") -- label:
expect_syntax(1, 8, "gbasicLabelName", "Label") -- state1
expect_syntax(2, 1, "gbasicConditional", "Conditional") -- if
expect_syntax(2, 4, "gbasicSensorReadOnly", "Special") -- m_depth
expect_syntax(2, 12, "gbasicOperator", "Operator") -- >
expect_syntax(2, 14, "gbasicFloat", "Float") -- 15.0
expect_syntax(2, 19, "gbasicConditional", "Conditional") -- then
expect_syntax(3, 3, "gbasicSensor", "Special") -- SCI_RUHP_BEHS
expect_syntax(3, 19, "gbasicNumber", "Number") -- 128
expect_syntax(4, 3, "gbasicGoto", "Statement") -- goto
expect_syntax(4, 8, "gbasicLabelName", "Label") -- state2
expect_syntax(5, 1, "gbasicConditional", "Conditional") -- endif
expect_syntax(6, 1, "gbasicStatement", "Statement") -- yield
expect_syntax(18, 1, "gbasicComment", "Comment") -- ' a comment
expect_syntax(18, 20, "gbasicComment", "Comment") -- goto inside the comment
expect_syntax(19, 1, "gbasicDeclaration", "Keyword") -- dim
expect_syntax(19, 5, "gbasicIdentifier", "Identifier") -- depths
expect_syntax(19, 19, "gbasicType", "Type") -- float (a type)
expect_syntax(20, 5, "gbasicBuiltin", "Function") -- float( (a built-in)
expect_syntax(20, 16, "gbasicBuiltin", "Function") -- abs(
expect_syntax(20, 20, "gbasicSensor", "Special") -- c_pitch
expect_syntax(20, 29, "gbasicComment", "Comment") -- ' trailing
expect_syntax(21, 1, "gbasicComment", "Comment") -- rem
expect_syntax(22, 1, "gbasicStatement", "Statement") -- print
expect_syntax(22, 7, "gbasicString", "String") -- "it's ...
expect_syntax(22, 11, "gbasicString", "String") -- the ' inside the string is no comment
expect_syntax(22, 13, "gbasicQuote", "SpecialChar") -- ""
expect_syntax(22, 25, "gbasicSensor", "Special") -- sci_water_temp

-- Indentation: `=` re-indents a block the way the README promises.
local scratch = H.edit(dir .. "/indent.gbas")
vim.api.nvim_buf_set_lines(scratch, 0, -1, false, {
  "for i = 0 to 9",
  "if depths(i) > 2.0 then",
  "print i",
  "ElseIf depths(i) < 1.0 Then",
  "print -i",
  "else",
  "exit for",
  "end if",
  "if i = 3 then print i",
  "next i",
  "do while i < 5",
  "loop",
})
vim.cmd("silent normal! gg=G")
H.equal(vim.api.nvim_buf_get_lines(scratch, 0, -1, false), {
  "for i = 0 to 9",
  "  if depths(i) > 2.0 then",
  "    print i",
  "  ElseIf depths(i) < 1.0 Then",
  "    print -i",
  "  else",
  "    exit for",
  "  end if",
  "  if i = 3 then print i",
  "next i",
  "do while i < 5",
  "loop",
}, "gg=G indents GBASIC blocks (if/elseif/else/end if, for/next, do/loop; one-line if stays)")

-- GLOC -----------------------------------------------------------------------------------------
local gloc = H.edit(gloc_path)
H.equal(vim.bo[gloc].filetype, "gloc", ".gloc has filetype gloc")
H.equal(vim.b[gloc].current_syntax, "gloc", "syntax/gloc.vim is loaded")
H.equal(vim.bo[gloc].commentstring, "# %s", "GLOC commentstring is # %s")
expect_syntax(1, 1, "glocHeader", "PreProc") -- nregs
expect_syntax(1, 7, "glocNumber", "Number") -- 8
expect_syntax(4, 1, "glocLabelKeyword", "Label") -- label
expect_syntax(4, 7, "glocLabelNumber", "Label") -- 0
expect_syntax(5, 1, "glocSensorInstruction", "Statement") -- loads
expect_syntax(5, 7, "glocSensorIndex", "Special") -- 444
expect_syntax(5, 11, "glocRegister", "Identifier") -- r0
expect_syntax(6, 7, "glocFloat", "Float") -- 15.0
expect_syntax(7, 1, "glocInstruction", "Statement") -- cmpgt
expect_syntax(8, 1, "glocControl", "Conditional") -- cbr
expect_syntax(8, 5, "glocRegister", "Identifier") -- r2
expect_syntax(8, 8, "glocLabelReference", "Label") -- 3
expect_syntax(8, 10, "glocLabelReference", "Label") -- 4
expect_syntax(10, 7, "glocNumber", "Number") -- 128 (loadi: a plain number)
expect_syntax(11, 11, "glocSensorIndex", "Special") -- 1387
expect_syntax(12, 7, "glocLabelReference", "Label") -- jumpi 1
expect_syntax(14, 1, "glocControl", "Conditional") -- yield
expect_syntax(31, 8, "glocString", "String") -- "depth # now"
expect_syntax(31, 16, "glocString", "String") -- the # inside the string is no comment
expect_syntax(31, 22, "glocComment", "Comment") -- # a comment

-- Every mnemonic and header word of docs/gloc.md is highlighted, in either case.
local words = {}
for _, line in ipairs(vim.fn.readfile(H.repo .. "/docs/gloc.md")) do
  local word = line:match("^| `([a-z][a-z0-9]*)[ `]")
  if word and not vim.tbl_contains(words, word) then
    words[#words + 1] = word
  end
end
H.check(#words >= 40, "docs/gloc.md lists the header words and the mnemonics", words)
local mnemonics = H.edit(dir .. "/mnemonics.gloc")
local lines = {}
for _, word in ipairs(words) do
  lines[#lines + 1] = word
  lines[#lines + 1] = word:upper()
end
vim.api.nvim_buf_set_lines(mnemonics, 0, -1, false, lines)
local unknown = {}
for index, line in ipairs(lines) do
  local name, linked = H.syntax_at(index, 1)
  if not (name:match("^gloc") and vim.tbl_contains({ "Statement", "Conditional", "PreProc", "Label" }, linked)) then
    unknown[#unknown + 1] = line .. " → " .. name
  end
end
H.equal(unknown, {}, "syntax/gloc.vim highlights every word of docs/gloc.md as a keyword")

-- :checkhealth gloc ---------------------------------------------------------------------------
local function health_lines()
  vim.cmd("silent checkhealth gloc")
  local lines = vim.api.nvim_buf_get_lines(0, 0, -1, false)
  vim.cmd("bwipeout!")
  return table.concat(lines, "\n")
end
local report = health_lines()
H.check(report:find("OK " .. vim.fn.exepath(H.gloc_bin) .. ": gloc ", 1, true) ~= nil,
  ":checkhealth gloc finds the binary and its version", report)
H.check(report:find("nvim-dap is not installed", 1, true) ~= nil, ":checkhealth gloc reports nvim-dap missing", report)
local configured = require("gloc").options.gloc_path
require("gloc").options.gloc_path = "/nonexistent/gloc"
report = health_lines()
require("gloc").options.gloc_path = configured
H.check(report:find('ERROR "/nonexistent/gloc" is not an executable', 1, true) ~= nil,
  ":checkhealth gloc reports a missing binary with advice", report)
H.check(report:find("cargo install --path cli", 1, true) ~= nil, ":checkhealth gloc says how to install gloc", report)

-- nvim-dap -------------------------------------------------------------------------------------
-- nvim-dap cannot be installed offline: setup() already ran with dap = true and must not have
-- failed; setup_dap() reports the absence with false.
local gloc_module = require("gloc")
H.equal(gloc_module.setup_dap(), false, "setup_dap() returns false when nvim-dap is absent")

-- With a stand-in `dap` module, the adapter and the configurations are registered, and every
-- launch attribute is one the VS Code extension declares (those `gloc dap` accepts).
local fake_dap = { adapters = {}, configurations = {} }
package.loaded["dap"] = fake_dap
H.equal(gloc_module.setup_dap(), true, "setup_dap() returns true when nvim-dap is present")
H.equal(fake_dap.adapters.gloc, { type = "executable", command = H.gloc_bin, args = { "dap" } }, "dap.adapters.gloc runs `gloc dap`")
H.check(fake_dap.configurations.gbasic ~= nil and fake_dap.configurations.gbasic == fake_dap.configurations.gloc,
  "dap.configurations for gbasic and gloc")
local manifest = vim.json.decode(table.concat(vim.fn.readfile(H.repo .. "/editors/vscode/package.json"), "\n"))
local declared = manifest.contributes.debuggers[1].configurationAttributes.launch.properties
for _, configuration in ipairs(fake_dap.configurations.gbasic or {}) do
  for key in pairs(configuration) do
    H.check(declared[key] ~= nil or key == "type" or key == "request" or key == "name",
      ("nvim-dap configuration %q: attribute %q is a declared launch attribute"):format(configuration.name, key))
  end
  H.equal(configuration.program, "${file}", ("nvim-dap configuration %q flies the current file"):format(configuration.name))
end
-- Over TCP the adapter is a function that starts `gloc dap --port 0` and reads its line.
H.equal({ gloc_module.parse_listening("gloc dap: listening on 127.0.0.1:4711 token 0a1b2c") }, { 4711, "0a1b2c" },
  "parse_listening reads the port and the token")
H.equal(gloc_module.parse_listening("gloc dap: listening on 127.0.0.1:4711"), nil,
  "parse_listening wants the token")
H.equal(gloc_module.setup_dap(vim.tbl_extend("force", gloc_module.options, { dap_transport = "tcp" })), true,
  "setup_dap() with dap_transport = tcp")
H.equal(type(fake_dap.adapters.gloc), "function", "dap.adapters.gloc is a server adapter function over TCP")
local connected = nil
fake_dap.adapters.gloc(function(adapter) connected = adapter end, { type = "gloc", request = "launch" })
H.check(vim.wait(10000, function() return connected ~= nil end), "the TCP adapter connects to `gloc dap --port 0`")
if connected then
  H.equal(connected.type, "server", "a server adapter")
  H.equal(connected.host, "127.0.0.1", "on loopback")
  local enriched = nil
  connected.enrich_config({ program = "x.gbas" }, function(config) enriched = config end)
  H.check(enriched ~= nil and type(enriched.token) == "string" and #enriched.token == 32,
    "enrich_config adds the session token")
end
package.loaded["dap"] = nil

-- The masterdata path travels once, in the `gloc` settings the server asks for
-- (workspace/configuration), not also in init_options.
local lsp_config = require("gloc").lsp_config({ gloc_path = "gloc", masterdata = "/glider/masterdata" })
H.equal({ lsp_config.init_options, lsp_config.settings.gloc.masterdata }, { nil, "/glider/masterdata" },
  "the masterdata path is sent once, in settings")

H.finish()
