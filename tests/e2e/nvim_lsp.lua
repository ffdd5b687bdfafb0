-- Drives a real Neovim (0.7+) as an LSP client of `ladder lsp`, for tests/test_editor_neovim.py.
--   nvim --headless -u NONE -i NONE -c "luafile nvim_lsp.lua"   with LADDER_NVIM_CONFIG=config.json
-- config: { rtp, cmd, out, bad, hover_name, fixed_lines, complete_name, detect = {path = expected filetype},
--          sim (optional), own_k (optional: a file opened after the user maps K themselves) }
-- Writes a JSON object of results per step to config.out, then quits. Each step records its
-- result or its error, so that one missing server feature does not hide the others.
local config = vim.fn.json_decode(table.concat(vim.fn.readfile(os.getenv('LADDER_NVIM_CONFIG')), '\n'))
local results = { steps = {}, version = vim.version() }

local function now()
  return vim.loop.hrtime() / 1e9
end

local function step(name, fn)
  local t = now()
  local ok, value = xpcall(fn, debug.traceback)
  results.steps[name] = { ok = ok, value = ok and value or nil, error = not ok and tostring(value) or nil,
    seconds = now() - t }
  return ok and value or nil
end

local function wait(ms, what, cond)
  if not vim.wait(ms, cond, 50) then
    error('timed out after ' .. ms .. ' ms waiting for ' .. what)
  end
end

local function hover_text(result)
  if not result or not result.contents then
    return nil
  end
  local c = result.contents
  if type(c) == 'string' then
    return c
  end
  if c.value then
    return c.value
  end
  local parts = {}
  for _, p in ipairs(c) do
    table.insert(parts, type(p) == 'string' and p or p.value)
  end
  return table.concat(parts, '\n')
end

local function first_result(responses)
  for _, r in pairs(responses or {}) do
    if r.error then
      error('server error: ' .. vim.inspect(r.error))
    end
    if r.result ~= nil then
      return r.result
    end
  end
  return nil
end

local function find(bufnr, word)
  for i, line in ipairs(vim.api.nvim_buf_get_lines(bufnr, 0, -1, false)) do
    local col = line:find(word, 1, true)
    if col then
      return i - 1, col - 1
    end
  end
  error(word .. ' not found in the buffer')
end

vim.opt.runtimepath:prepend(config.rtp)
vim.opt.swapfile = false

-- 1. filetype detection by the plugin's ftdetect/ladder.vim (first lines of .ld and .txt files)
step('filetypes', function()
  vim.cmd('filetype on')
  local out = {}
  for path, _ in pairs(config.detect or {}) do
    vim.cmd('edit ' .. vim.fn.fnameescape(path))
    out[path] = vim.bo.filetype
    vim.cmd('bwipeout!')
  end
  return out
end)

local ladder = require('ladder')
ladder.setup({ cmd = config.cmd, settings = { diagnosticsDelayMs = 50, compileOnSave = false } })

local bufnr
-- 2. open the program: the client attaches and the diagnostic arrives on the right line
step('attach', function()
  vim.cmd('edit ' .. vim.fn.fnameescape(config.bad))
  bufnr = vim.api.nvim_get_current_buf()
  wait(20000, 'the client to attach', function()
    local clients = vim.lsp.buf_get_clients(bufnr)
    for _, c in pairs(clients) do
      if c.name == 'ladder' and c.initialized ~= false then
        return true
      end
    end
    return false
  end)
  return vim.bo.filetype
end)

step('diagnostics', function()
  wait(20000, 'diagnostics', function()
    return #vim.diagnostic.get(bufnr) > 0
  end)
  local out = {}
  for _, d in ipairs(vim.diagnostic.get(bufnr)) do
    table.insert(out, { lnum = d.lnum, col = d.col, end_col = d.end_col, message = d.message, code = d.code,
      severity = d.severity, source = d.source })
  end
  return out
end)

-- 3. hover a name
step('hover', function()
  local line, col = find(bufnr, config.hover_name)
  local params = { textDocument = { uri = vim.uri_from_bufnr(bufnr) }, position = { line = line, character = col + 1 } }
  local result = first_result(vim.lsp.buf_request_sync(bufnr, 'textDocument/hover', params, 10000))
  return hover_text(result)
end)

-- 4. fix the program: the diagnostic clears
step('fix', function()
  vim.api.nvim_buf_set_lines(bufnr, 0, -1, false, config.fixed_lines)
  wait(20000, 'the diagnostics to clear', function()
    return #vim.diagnostic.get(bufnr) == 0
  end)
  return true
end)

-- 5. format
step('format', function()
  local before = vim.api.nvim_buf_get_lines(bufnr, 0, -1, false)
  if vim.lsp.buf.format then
    vim.lsp.buf.format({ bufnr = bufnr, timeout_ms = 10000 })
  else
    vim.lsp.buf.formatting_sync(nil, 10000)
  end
  local after = vim.api.nvim_buf_get_lines(bufnr, 0, -1, false)
  return { changed = not vim.deep_equal(before, after), lines = after }
end)

local function floating_text()
  for _, win in ipairs(vim.api.nvim_list_wins()) do
    if vim.api.nvim_win_get_config(win).relative ~= '' then
      return table.concat(vim.api.nvim_buf_get_lines(vim.api.nvim_win_get_buf(win), 0, -1, false), '\n'), win
    end
  end
  return nil
end

-- 6. what the buffer got when the server attached: K shows the hover (the plugin's mapping before
-- 0.10, Neovim's own after), <C-x><C-o> completes names ('omnifunc')
step('hover_key', function()
  local map = vim.fn.maparg('K', 'n', false, true)
  local line, col = find(bufnr, config.hover_name)
  vim.api.nvim_win_set_cursor(0, { line + 1, col + 1 })
  vim.cmd('normal K')
  wait(10000, 'the hover window', function()
    return floating_text() ~= nil
  end)
  local text, win = floating_text()
  vim.api.nvim_win_close(win, true)
  return { desc = map.desc or map.rhs, buffer = map.buffer, text = text }
end)

step('omnifunc', function()
  local line, col = find(bufnr, config.complete_name)
  vim.api.nvim_win_set_cursor(0, { line + 1, col + 1 })
  local words, deadline = nil, vim.loop.now() + 10000
  -- the items arrive while Insert mode waits (feedkeys 'x!'); a timer reads them and leaves
  vim.fn.timer_start(50, function(timer)
    local info = vim.fn.complete_info({ 'items' })
    if #info.items > 0 or vim.loop.now() > deadline then
      vim.fn.timer_stop(timer)
      words = {}
      for _, item in ipairs(info.items) do
        table.insert(words, item.word)
      end
      vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes('<C-e><Esc>', true, false, true), 'n', false)
    end
  end, { ['repeat'] = -1 })
  vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes('i<C-x><C-o>', true, false, true), 'x!', false)
  return { omnifunc = vim.bo[bufnr].omnifunc, words = words }
end)

step('checkhealth', function()
  vim.cmd('checkhealth ladder')
  local lines = vim.api.nvim_buf_get_lines(0, 0, -1, false)
  vim.cmd('tabclose')
  return table.concat(lines, '\n')
end)

-- 7. the simulation: energized elements as extmarks, values as virtual text
if config.sim then
  local sbuf
  step('sim_start', function()
    vim.cmd('edit ' .. vim.fn.fnameescape(config.sim))
    sbuf = vim.api.nvim_get_current_buf()
    wait(20000, 'the client to attach', function()
      return #vim.lsp.buf_get_clients(sbuf) > 0
    end)
    vim.cmd('LadderSimStart')
    wait(20000, 'the simulation state', function()
      return ladder.states[sbuf] ~= nil
    end)
    return ladder.status(sbuf)
  end)
  step('sim_step', function()
    local scan = ladder.states[sbuf].scan
    vim.cmd('LadderSimToggle Xstart')
    wait(10000, 'Xstart = 1', function()
      return ladder.states[sbuf] and ladder.states[sbuf].values.Xstart == 1
    end)
    vim.cmd('LadderSimStep')
    wait(10000, 'the next scan', function()
      return ladder.states[sbuf] and ladder.states[sbuf].scan > scan
    end)
    local marks = vim.api.nvim_buf_get_extmarks(sbuf, ladder.ns, 0, -1, { details = true })
    local lines = vim.api.nvim_buf_get_lines(sbuf, 0, -1, false)
    local energized, virt = {}, {}
    for _, m in ipairs(marks) do
      local row, col, d = m[2], m[3], m[4]
      if d.hl_group == 'LadderEnergized' then
        table.insert(energized, { row = row, col = col, end_col = d.end_col,
          text = lines[row + 1]:sub(col + 1, d.end_col) })
      elseif d.virt_text then
        table.insert(virt, { row = row, text = d.virt_text[1][1] })
      end
    end
    return { status = ladder.status(sbuf), energized = energized, virt_text = virt }
  end)
  step('sim_stop', function()
    vim.cmd('LadderSimStop')
    wait(10000, 'the marks to clear', function()
      return ladder.states[sbuf] == nil
        and #vim.api.nvim_buf_get_extmarks(sbuf, ladder.ns, 0, -1, {}) == 0
    end)
    return true
  end)
end

-- 8. a user who maps K themselves keeps their mapping
if config.own_k then
  step('own_k', function()
    vim.keymap.set('n', 'K', '<Cmd>echo "mine"<CR>')
    vim.cmd('edit ' .. vim.fn.fnameescape(config.own_k))
    local buf = vim.api.nvim_get_current_buf()
    wait(20000, 'the client to attach', function()
      return #vim.lsp.buf_get_clients(buf) > 0
    end)
    vim.wait(300) -- let a later on_attach (0.11+ attaches after the open) have its go
    local map = vim.fn.maparg('K', 'n', false, true)
    return { rhs = map.rhs, buffer = map.buffer }
  end)
end

vim.fn.writefile({ vim.fn.json_encode(results) }, config.out)
vim.cmd('qa!')
