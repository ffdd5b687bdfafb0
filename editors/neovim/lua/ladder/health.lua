-- :checkhealth ladder — is the language server there: the command Neovim runs, the textladder
-- version it reports (`ladder --version`) and the Python it runs in.
-- Neovim 0.10+ reports with vim.health.start/ok/...; 0.7 to 0.9 with require('health').report_*.
local M = {}

local health = vim.health or require('health')
local report = {
  start = health.start or health.report_start,
  ok = health.ok or health.report_ok,
  info = health.info or health.report_info,
  warn = health.warn or health.report_warn,
  error = health.error or health.report_error,
}

local INSTALL = {
  'Install textladder into a virtual environment: python3 -m venv ~/.venvs/textladder && '
    .. '~/.venvs/textladder/bin/pip install /path/to/textladder',
  "then point the plugin at it: require('ladder').setup({ python = '~/.venvs/textladder/bin/python' }), "
    .. 'or put its bin folder on PATH',
}

--- The command Neovim runs for the server: a running client's, else the 0.11+ configuration's
--- (setup() registers there too), else the plugin's.
local function server_cmd()
  local get = vim.lsp.get_clients or vim.lsp.get_active_clients
  for _, client in ipairs(get()) do
    if client.name == 'ladder' and type(client.config.cmd) == 'table' then
      return client.config.cmd, 'the running client'
    end
  end
  if vim.lsp.config then
    local ok, config = pcall(function()
      return vim.lsp.config.ladder
    end)
    if ok and type(config) == 'table' and type(config.cmd) == 'table' then
      return config.cmd, "vim.lsp.config('ladder')"
    end
  end
  return require('ladder').server_cmd(), "require('ladder').setup()"
end

local function run(cmd)
  local out = vim.fn.system(cmd)
  return vim.v.shell_error == 0, vim.trim(out or '')
end

--- The interpreter a console script runs: the one on its `#!` line (pip writes `#!/bin/sh` and
--- an `exec` line when the path has blanks or is long), else a `python` beside it (a venv's bin).
local function script_python(exe)
  local ok, lines = pcall(vim.fn.readfile, exe, '', 2)
  if ok then
    local first = lines[1] or ''
    local interpreter = first:match('^#!%s*(.-)%s*$')
    if interpreter == '/bin/sh' then
      interpreter = (lines[2] or ''):match([[^'''exec' "([^"]+)"]]) or (lines[2] or ''):match([[^'''exec' (%S+)]])
    elseif interpreter and interpreter:match('/env%s') then
      interpreter = vim.fn.exepath(interpreter:match('/env%s+(%S+)'))
    end
    if interpreter and interpreter ~= '' and vim.fn.executable(interpreter) == 1 then
      return interpreter
    end
  end
  local folder = vim.fn.fnamemodify(exe, ':h')
  for _, name in ipairs({ 'python', 'python3', 'python.exe' }) do
    local candidate = folder .. '/' .. name
    if vim.fn.executable(candidate) == 1 then
      return candidate
    end
  end
  return nil
end

function M.check()
  report.start('ladder: the language server')
  local cmd, source = server_cmd()
  report.info('command (from ' .. source .. '): ' .. table.concat(cmd, ' '))
  local exe = vim.fn.exepath(vim.fn.expand(cmd[1]))
  if exe == '' then
    report.error('`' .. cmd[1] .. '` not found', INSTALL)
    return
  end
  report.ok('found: ' .. exe)

  -- the arguments before `lsp` (a Python's `-m ladder`), then --version
  local version_cmd = { exe }
  for i = 2, #cmd do
    if cmd[i] == 'lsp' then
      break
    end
    table.insert(version_cmd, cmd[i])
  end
  table.insert(version_cmd, '--version')
  local ok, version = run(version_cmd)
  if ok and version:match('^ladder ') then
    report.ok('version: ' .. version)
  else
    report.error('`' .. table.concat(version_cmd, ' ') .. '` failed: ' .. version, INSTALL)
  end

  local python = cmd[2] == '-m' and exe or script_python(exe)
  if not python then
    report.warn('Python: cannot tell which Python ' .. exe .. ' runs')
    return
  end
  local python_ok, python_version = run({ python, '--version' })
  if python_ok then
    report.ok('Python: ' .. python .. ' (' .. python_version .. ')')
  else
    report.error('Python: ' .. python .. ' does not run: ' .. python_version)
  end
end

return M
