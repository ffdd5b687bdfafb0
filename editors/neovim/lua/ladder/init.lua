-- textladder for Neovim: starts `ladder lsp` for ladder/ldmicro buffers and shows the simulation
-- (docs/lsp-protocol.md): energized elements highlighted red, values and the scan as virtual text,
-- and :LadderSim* commands. Works on Neovim 0.7 and later; see docs/editors.md.
--
--   require('ladder').setup({
--     cmd = nil,            -- server command, e.g. { '/path/to/venv/bin/ladder', 'lsp' }
--     python = nil,         -- or a Python with textladder: runs { python, '-m', 'ladder', 'lsp' }
--     settings = {},        -- sent as the `ladder` settings section (compileOnSave, encoding, ...)
--     autostart = true,     -- start the client for ladder/ldmicro buffers
--     virtual_text = true,  -- show values and the scan as virtual text
--     hover_key = 'K',      -- hover on this key where Neovim maps none (before 0.10); false: none
--   })
--
-- Pieces for your own client set-up: require('ladder').handlers (the `ladder/simulationState`
-- handler), .on_attach (hover key and omnifunc), .create_commands(), .filetype_rule(),
-- .server_cmd(opts). `:checkhealth ladder` checks the server (lua/ladder/health.lua).
local M = {}

M.ns = vim.api.nvim_create_namespace('ladder_simulation')

M.config = {
  cmd = nil,
  python = nil,
  settings = {},
  autostart = true,
  virtual_text = true,
  hover_key = 'K',
  root_markers = { '.git' },
}

-- last simulation state per buffer (only while a simulation runs)
M.states = {}

local clients_by_root = {}

local function notify(msg, level)
  vim.notify('ladder: ' .. msg, level or vim.log.levels.INFO)
end

--------------------------------------------------------------------------- server command

--- The command that starts the server: opts.cmd, else { opts.python, '-m', 'ladder', 'lsp' },
--- else { 'ladder', 'lsp' }.
function M.server_cmd(opts)
  opts = opts or M.config
  if opts.cmd and #opts.cmd > 0 then
    return opts.cmd
  end
  if opts.python and opts.python ~= '' then
    return { vim.fn.expand(opts.python), '-m', 'ladder', 'lsp' }
  end
  return { 'ladder', 'lsp' }
end

local function root_dir(bufnr)
  local name = vim.api.nvim_buf_get_name(bufnr)
  local dir = name ~= '' and vim.fn.fnamemodify(name, ':p:h') or vim.fn.getcwd()
  for _, marker in ipairs(M.config.root_markers or {}) do
    local found = vim.fn.finddir(marker, dir .. ';')
    if found == '' then
      found = vim.fn.findfile(marker, dir .. ';')
    end
    if found ~= '' then
      return vim.fn.fnamemodify(found, ':p:h:h')
    end
  end
  return dir
end

--------------------------------------------------------------------------- filetypes

--- `.ladder` files, and `.ld`/`.txt` files whose first line is LDmicro's: most `.ld` files are
--- linker scripts, most `.txt` files text. (ftdetect/ladder.vim does the same when this folder
--- is on 'runtimepath' at start-up.)
function M.filetype_rule()
  local group = vim.api.nvim_create_augroup('ladder_filetype', { clear = true })
  vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, {
    group = group,
    pattern = { '*.ladder', '*.ld', '*.txt', '*.TXT' },
    callback = function(args)
      local ft = M.detect(args.buf, args.file or args.match)
      if ft then
        vim.api.nvim_buf_set_option(args.buf, 'filetype', ft)
      end
    end,
  })
end

--- The filetype of a buffer by its name and first line, or nil when it is not a ladder program.
function M.detect(bufnr, name)
  name = name or vim.api.nvim_buf_get_name(bufnr)
  local first = vim.api.nvim_buf_get_lines(bufnr, 0, 1, false)[1] or ''
  if name:match('%.ladder$') then
    return 'ladder'
  end
  if first:match('^LDmicro export text') then
    return 'ladder'
  end
  if name:lower():match('%.ld$') and first:match('^LDmicro') then
    return 'ldmicro'
  end
  return nil
end

--------------------------------------------------------------------------- clients

local function ladder_clients(bufnr)
  local out = {}
  if vim.lsp.get_clients then
    return vim.lsp.get_clients({ bufnr = bufnr, name = 'ladder' })
  end
  for _, client in pairs(vim.lsp.buf_get_clients(bufnr)) do
    if client.name == 'ladder' then
      table.insert(out, client)
    end
  end
  return out
end

local function request(client, method, params, handler, bufnr)
  if vim.fn.has('nvim-0.11') == 1 then
    return client:request(method, params, handler, bufnr)
  end
  return client.request(method, params, handler, bufnr)
end

--- What a buffer gets once the server is attached to it, where Neovim gives nothing itself:
--- completion with <C-x><C-o> (Neovim sets 'omnifunc' from 0.8) and hover on `hover_key` (Neovim
--- maps K from 0.10). A user's own 'omnifunc' or mapping of the key stays as it is.
function M.on_attach(_, bufnr)
  if vim.fn.has('nvim-0.8') == 0 and vim.bo[bufnr].omnifunc == '' then
    vim.bo[bufnr].omnifunc = 'v:lua.vim.lsp.omnifunc'
  end
  local key = M.config.hover_key
  if not key or key == '' or (key == 'K' and vim.fn.has('nvim-0.10') == 1) then
    return
  end
  local taken = vim.api.nvim_buf_call(bufnr, function()
    return vim.fn.maparg(key, 'n') ~= ''
  end)
  if not taken then
    vim.keymap.set('n', key, vim.lsp.buf.hover, { buffer = bufnr, desc = 'ladder: hover' })
  end
end

--- Starts (or reuses) the client for a buffer's project and attaches the buffer: the
--- `vim.lsp.start_client` set-up of Neovim 0.7 to 0.10.
function M.start(bufnr)
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  local root = root_dir(bufnr)
  local id = clients_by_root[root]
  local client = id and vim.lsp.get_client_by_id(id)
  if not client or client.is_stopped() then
    id = vim.lsp.start_client({
      name = 'ladder',
      cmd = M.server_cmd(),
      root_dir = root,
      handlers = M.handlers,
      settings = { ladder = M.config.settings or {} },
      on_attach = M.on_attach,
      on_exit = function()
        clients_by_root[root] = nil
        vim.schedule(M.clear_all)
      end,
    })
    if not id then
      notify('could not start ' .. table.concat(M.server_cmd(), ' '), vim.log.levels.ERROR)
      return nil
    end
    clients_by_root[root] = id
  end
  vim.lsp.buf_attach_client(bufnr, id)
  return id
end

--------------------------------------------------------------------------- simulation display

vim.cmd([[
  highlight default LadderEnergized guifg=#ff3030 ctermfg=Red gui=bold cterm=bold
  highlight default link LadderSimStatus DiagnosticInfo
  highlight default link LadderSimValue Comment
]])

local function byte_col(line, utf16)
  -- LSP columns count UTF-16 units; buffer columns count bytes
  if not line:find('[\128-\255]') then
    return math.min(utf16, #line)
  end
  local units, i = 0, 1
  while i <= #line and units < utf16 do
    local c = line:byte(i)
    local len = (c < 0x80 and 1) or (c < 0xE0 and 2) or (c < 0xF0 and 3) or 4
    units = units + (len == 4 and 2 or 1)
    i = i + len
  end
  return i - 1
end

local function format_time(ms)
  if type(ms) ~= 'number' then
    return '?'
  end
  if math.abs(ms) >= 1000 then
    return string.format('%.3f s', ms / 1000)
  end
  return (string.format('%.3f', ms):gsub('%.?0+$', '')) .. ' ms'
end
M.format_time = format_time

--- The lines of a buffer where names get their values shown: the diagram (ladder) or the
--- program (ldmicro). 0-based, end exclusive.
local function diagram_lines(bufnr, lines)
  local ft = vim.api.nvim_buf_get_option(bufnr, 'filetype')
  if ft == 'ldmicro' then
    for i, text in ipairs(lines) do
      if text:match('^PROGRAM%s*$') then
        return i, #lines
      end
    end
    return 0, #lines
  end
  local start, in_diagram = 0, false
  for i, text in ipairs(lines) do
    if text:match('^LADDER DIAGRAM%s*:') then
      start, in_diagram = i, true
    elseif in_diagram and text:match('^[%a/][^:|]*:%s*$') then
      return start, i - 1
    end
  end
  return start, #lines
end

--- One line of status: "sim paused 1.230 s · scan 123".
function M.status(bufnr)
  local state = M.states[bufnr or vim.api.nvim_get_current_buf()]
  if not state then
    return ''
  end
  return string.format('sim %s %s · scan %d', state.realtime and 'running' or 'paused', format_time(state.timeMs),
    state.scan or 0)
end

function M.render(bufnr)
  if not vim.api.nvim_buf_is_loaded(bufnr) then
    return
  end
  vim.api.nvim_buf_clear_namespace(bufnr, M.ns, 0, -1)
  local state = M.states[bufnr]
  if not state then
    return
  end
  local lines = vim.api.nvim_buf_get_lines(bufnr, 0, -1, false)
  for _, r in ipairs(state.energized or {}) do
    local srow, erow = r.start.line, r['end'].line
    if lines[srow + 1] and lines[erow + 1] then
      pcall(vim.api.nvim_buf_set_extmark, bufnr, M.ns, srow, byte_col(lines[srow + 1], r.start.character), {
        end_row = erow,
        end_col = byte_col(lines[erow + 1], r['end'].character),
        hl_group = 'LadderEnergized',
        priority = 200,
      })
    end
  end
  if not M.config.virtual_text then
    return
  end
  local status = '▶ ' .. M.status(bufnr) .. (state.error and ('  ✗ ' .. state.error) or '')
  vim.api.nvim_buf_set_extmark(bufnr, M.ns, 0, 0, {
    virt_text = { { status, state.error and 'DiagnosticError' or 'LadderSimStatus' } },
    virt_text_pos = 'eol',
  })
  local values = state.values or {}
  local first, last = diagram_lines(bufnr, lines)
  for i = first + 1, last do
    local text = lines[i]
    if text and not text:match('^%s*%d*|[|+]%s*;') then
      local shown, seen = {}, {}
      for name in text:gmatch('[%a_$][%w_]*') do
        if values[name] ~= nil and not seen[name] then
          seen[name] = true
          table.insert(shown, name .. '=' .. tostring(values[name]))
        end
      end
      if #shown > 0 then
        vim.api.nvim_buf_set_extmark(bufnr, M.ns, i - 1, 0, {
          virt_text = { { '  ' .. table.concat(shown, ' '), 'LadderSimValue' } },
          virt_text_pos = 'eol',
        })
      end
    end
  end
end

-- Neovim 0.12 hands over the server's JSON null as vim.NIL, which is truthy (0.7 to 0.11 gave nil):
-- `"error": null` would read as an error and stop the rendering before the values.
local function without_nulls(t)
  if type(t) ~= 'table' then
    return t
  end
  for k, v in pairs(t) do
    if v == vim.NIL then
      t[k] = nil
    end
  end
  return t
end

--- Takes a state from the server (notification or command result).
function M.on_state(state)
  if type(state) ~= 'table' or type(state.uri) ~= 'string' then
    return
  end
  without_nulls(state)
  without_nulls(state.values)
  local bufnr = vim.uri_to_bufnr(state.uri)
  if state.running then
    M.states[bufnr] = state
  else
    M.states[bufnr] = nil
  end
  M.render(bufnr)
  if state.error then
    notify('simulation: ' .. tostring(state.error), vim.log.levels.WARN)
  end
end

function M.clear_all()
  for bufnr in pairs(M.states) do
    M.states[bufnr] = nil
    if vim.api.nvim_buf_is_loaded(bufnr) then
      vim.api.nvim_buf_clear_namespace(bufnr, M.ns, 0, -1)
    end
  end
end

M.handlers = {
  ['ladder/simulationState'] = function(_, result)
    M.on_state(result)
  end,
}

--------------------------------------------------------------------------- commands

--- Runs a server command (docs/lsp-protocol.md) for a buffer; `on_result(result)` gets the
--- result. The document's URI is put first in the arguments.
function M.execute(command, args, bufnr, on_result)
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  local client = ladder_clients(bufnr)[1]
  if not client then
    notify('no ladder language server is attached to this buffer', vim.log.levels.ERROR)
    return
  end
  local arguments = { vim.uri_from_bufnr(bufnr) }
  for _, a in ipairs(args or {}) do
    table.insert(arguments, a)
  end
  request(client, 'workspace/executeCommand', { command = command, arguments = arguments }, function(err, result)
    if err then
      notify(err.message or tostring(err), vim.log.levels.ERROR)
      return
    end
    without_nulls(result)
    if type(result) == 'table' and result.uri and result.running ~= nil then
      M.on_state(result)
    end
    if on_result then
      on_result(result)
    end
  end, bufnr)
end

local function parse_ms(text)
  local n, unit = (text or ''):match('^%s*([%d%.]+)%s*(%a*)%s*$')
  n = tonumber(n)
  if not n then
    return nil
  end
  local factor = ({ [''] = 1, us = 0.001, ms = 1, s = 1000, min = 60000, h = 3600000 })[unit:lower()]
  return factor and n * factor or nil
end
M.parse_ms = parse_ms

local function input_names(bufnr)
  local state = M.states[bufnr or vim.api.nvim_get_current_buf()]
  local names = {}
  for name in pairs(state and state.values or {}) do
    table.insert(names, name)
  end
  table.sort(names)
  return names
end

function M.create_commands()
  local cmd = vim.api.nvim_create_user_command
  local function complete_names(prefix)
    return vim.tbl_filter(function(n)
      return n:sub(1, #prefix) == prefix
    end, input_names())
  end
  cmd('LadderSimStart', function()
    M.execute('ladder.sim.start')
  end, { desc = 'Start simulating the program in this buffer' })
  cmd('LadderSimStop', function()
    local bufnr = vim.api.nvim_get_current_buf()
    M.execute('ladder.sim.stop', {}, bufnr, function()
      M.states[bufnr] = nil
      M.render(bufnr)
    end)
  end, { desc = 'Stop the simulation' })
  cmd('LadderSimStep', function(o)
    M.execute('ladder.sim.step', { tonumber(o.args) or 1 })
  end, { nargs = '?', desc = 'Simulate N scans (default 1)' })
  cmd('LadderSimRunFor', function(o)
    local ms = parse_ms(o.args)
    if not ms then
      return notify('a duration: 500, 500ms, 2.5s', vim.log.levels.ERROR)
    end
    M.execute('ladder.sim.runFor', { ms })
  end, { nargs = 1, desc = 'Simulate for a time: 500, 500ms, 2.5s' })
  cmd('LadderSimRealtime', function(o)
    local state = M.states[vim.api.nvim_get_current_buf()]
    local on
    if o.args == 'on' then
      on = true
    elseif o.args == 'off' then
      on = false
    else
      on = not (state and state.realtime)
    end
    M.execute('ladder.sim.runRealtime', { on })
  end, {
    nargs = '?',
    complete = function()
      return { 'on', 'off' }
    end,
    desc = 'Run in real time (on/off; toggles without an argument)',
  })
  cmd('LadderSimRunUntil', function(o)
    M.execute('ladder.sim.runUntil', { o.args, 60000 }, 0, function(result)
      if type(result) == 'table' and result.reached ~= nil then
        notify(string.format('"%s" %s at %s', o.args, result.reached and 'reached' or 'not reached',
          format_time(result.timeMs)))
      end
    end)
  end, { nargs = '+', desc = 'Simulate until a condition holds, e.g. Yred = 1' })
  cmd('LadderSimReset', function()
    M.execute('ladder.sim.reset')
  end, { desc = 'Reset the simulation (EEPROM kept)' })
  cmd('LadderSimSet', function(o)
    local name, value = o.args:match('^%s*(%S+)%s*=?%s*(%S+)%s*$')
    if not name or not tonumber(value) then
      return notify('usage: :LadderSimSet NAME VALUE', vim.log.levels.ERROR)
    end
    M.execute('ladder.sim.set', { name, math.floor(tonumber(value)) })
  end, {
    nargs = '+',
    complete = complete_names,
    desc = 'Set an input or variable: NAME VALUE',
  })
  cmd('LadderSimToggle', function(o)
    local name = o.args ~= '' and o.args or vim.fn.expand('<cword>')
    M.execute('ladder.sim.toggle', { name })
  end, {
    nargs = '?',
    complete = complete_names,
    desc = 'Toggle an input (default: the name under the cursor)',
  })
  cmd('LadderSimValues', function()
    local state = M.states[vim.api.nvim_get_current_buf()]
    if not state then
      return notify('no simulation is running in this buffer')
    end
    local out = { M.status() }
    for _, name in ipairs(input_names()) do
      table.insert(out, string.format('%-24s %s', name, tostring(state.values[name])))
    end
    print(table.concat(out, '\n'))
  end, { desc = 'Print every value of the simulation' })
  cmd('LadderConvert', function(o)
    M.execute('ladder.convert', { o.args }, 0, function(result)
      if type(result) == 'table' and result.path then
        notify('wrote ' .. result.path)
      end
    end)
  end, {
    nargs = 1,
    complete = function()
      return { 'ladder', 'ld' }
    end,
    desc = 'Convert to .ladder or LDmicro .ld (written beside the file)',
  })
  cmd('LadderBuild', function()
    M.execute('ladder.build', {}, 0, function(result)
      if type(result) == 'table' then
        notify((result.ok and 'built: ' or 'build failed: ') .. tostring(result.summary or ''),
          result.ok and vim.log.levels.INFO or vim.log.levels.ERROR)
      end
    end)
  end, { desc = 'Compile the program to a HEX file' })
end

--------------------------------------------------------------------------- setup

function M.setup(opts)
  M.config = vim.tbl_deep_extend('force', M.config, opts or {})
  M.filetype_rule()
  M.create_commands()
  local group = vim.api.nvim_create_augroup('ladder_lsp', { clear = true })
  vim.api.nvim_create_autocmd('BufUnload', {
    group = group,
    callback = function(args)
      M.states[args.buf] = nil
    end,
  })
  if not M.config.autostart then
    return
  end
  if vim.lsp.config and vim.lsp.enable then
    -- Neovim 0.11+: the built-in configuration
    vim.lsp.config('ladder', {
      cmd = M.server_cmd(),
      filetypes = { 'ladder', 'ldmicro' },
      root_markers = M.config.root_markers,
      handlers = M.handlers,
      settings = { ladder = M.config.settings or {} },
      on_attach = M.on_attach,
    })
    vim.lsp.enable('ladder')
    return
  end
  vim.api.nvim_create_autocmd('FileType', {
    group = group,
    pattern = { 'ladder', 'ldmicro' },
    callback = function(args)
      M.start(args.buf)
    end,
  })
  -- buffers opened before setup()
  for _, bufnr in ipairs(vim.api.nvim_list_bufs()) do
    local ft = vim.api.nvim_buf_is_loaded(bufnr) and vim.api.nvim_buf_get_option(bufnr, 'filetype')
    if ft == 'ladder' or ft == 'ldmicro' then
      M.start(bufnr)
    end
  end
end

return M
