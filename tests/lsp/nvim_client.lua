-- Drives `rcxc lsp` from Neovim's own LSP client (headless), for
-- tests/lsp/nvim_test.cpp. g:rcxc_config names a JSON file with: rcxc (the
-- binary), file (the program to open), stdlib_dir, out (where the findings
-- go as JSON), the 0-based positions to ask about, rename_to, the new
-- name for the rename at `rename`, and symbol_query, a workspace symbol search (inlay hints are
-- asked over the whole buffer), callers, where to ask for incoming calls, and untidy, the
-- first of two lines made untidy before the second is range-formatted. Written for the
-- vim.lsp API of Neovim 0.7 (Debian 12) and later.
local result = {}
local function run()
  local cfg = vim.fn.json_decode(table.concat(vim.fn.readfile(vim.g.rcxc_config), "\n"))
  vim.cmd('edit ' .. vim.fn.fnameescape(cfg.file))
  vim.bo.filetype = 'nqc'
  local client_id = vim.lsp.start_client({
    name = 'rcxc',
    cmd = { cfg.rcxc, 'lsp', '--stdlib-dir', cfg.stdlib_dir },
    root_dir = vim.fn.fnamemodify(cfg.file, ':p:h'),
  })
  assert(client_id, 'rcxc lsp did not start')
  vim.lsp.buf_attach_client(0, client_id)
  result.attached = vim.wait(10000, function() return #vim.diagnostic.get(0) > 0 end, 20)

  result.diagnostics = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    table.insert(result.diagnostics, { lnum = d.lnum, col = d.col, end_lnum = d.end_lnum, end_col = d.end_col,
                                       severity = d.severity, message = d.message })
  end

  local function at(pos)
    return { textDocument = vim.lsp.util.make_text_document_params(), position = { line = pos[1], character = pos[2] } }
  end
  local function ask(method, params)
    local replies, err = vim.lsp.buf_request_sync(0, method, params, 10000)
    assert(replies, method .. ': ' .. tostring(err))
    local reply = replies[client_id]
    assert(reply and not reply.err, method .. ' failed: ' .. vim.inspect(reply))
    return reply.result
  end

  local hover = ask('textDocument/hover', at(cfg.hover))
  result.hover = hover and hover.contents and hover.contents.value or vim.NIL

  local completion = ask('textDocument/completion', at(cfg.completion))
  result.completion = {}
  for _, item in ipairs(completion.items or completion) do table.insert(result.completion, item.label) end

  local def = ask('textDocument/definition', at(cfg.definition))
  if def and def[1] then def = def[1] end
  result.definition = def and { uri = def.uri, line = def.range.start.line, character = def.range.start.character } or vim.NIL

  local help = ask('textDocument/signatureHelp', at(cfg.signature))
  result.signature = help and help.signatures[1] and help.signatures[1].label or vim.NIL

  -- Inlay hints over the whole buffer. Neovim 0.7 shows none itself, so
  -- the request is sent as a newer client sends it.
  local hints = ask('textDocument/inlayHint', { textDocument = vim.lsp.util.make_text_document_params(),
    range = { start = { line = 0, character = 0 }, ['end'] = { line = vim.api.nvim_buf_line_count(0), character = 0 } } })
  result.hints = {}
  for _, h in ipairs(hints or {}) do
    table.insert(result.hints, { line = h.position.line, character = h.position.character, label = h.label })
  end

  -- Workspace symbols as a user asks for them: the client's handler fills
  -- the quickfix list and opens its window, closed again for what follows.
  vim.fn.setqflist({}, 'r')
  vim.lsp.buf.workspace_symbol(cfg.symbol_query)
  vim.wait(10000, function() return #vim.fn.getqflist() > 0 end, 20)
  vim.cmd('cclose')
  result.symbols = {}
  for _, item in ipairs(vim.fn.getqflist()) do
    table.insert(result.symbols, { lnum = item.lnum, col = item.col, text = item.text })
  end

  -- Incoming calls as a user asks for them: the client prepares the item
  -- under the cursor, asks for its callers and fills the quickfix list.
  vim.fn.setqflist({}, 'r')
  vim.api.nvim_win_set_cursor(0, { cfg.callers[1] + 1, cfg.callers[2] })
  vim.lsp.buf.incoming_calls()
  vim.wait(10000, function() return #vim.fn.getqflist() > 0 end, 20)
  vim.cmd('cclose')
  result.callers = {}
  for _, item in ipairs(vim.fn.getqflist()) do
    table.insert(result.callers, { lnum = item.lnum, col = item.col, text = item.text })
  end

  -- Rename as a user does it: the client asks prepareRename, then rename,
  -- and applies the edit to the buffer.
  vim.o.hidden = true  -- the jump below leaves the renamed buffer unsaved
  vim.api.nvim_win_set_cursor(0, { cfg.rename[1] + 1, cfg.rename[2] })
  local before = table.concat(vim.api.nvim_buf_get_lines(0, 0, -1, false), '\n')
  vim.lsp.buf.rename(cfg.rename_to)
  vim.wait(10000, function() return table.concat(vim.api.nvim_buf_get_lines(0, 0, -1, false), '\n') ~= before end, 20)
  result.renamed = vim.api.nvim_buf_get_lines(0, 0, -1, false)

  -- Format selection as a user does it: two lines made untidy, only the
  -- second selected; the client applies the server's edits.
  vim.api.nvim_buf_set_lines(0, cfg.untidy, cfg.untidy + 2, false, { 'OnRev( OUT_A );', 'Wait(  50 );' })
  local untidy = table.concat(vim.api.nvim_buf_get_lines(0, 0, -1, false), '\n')
  vim.bo.shiftwidth = 2  -- sent as the tab size, the indent (without it: 8)
  vim.lsp.buf.range_formatting({}, { cfg.untidy + 2, 0 }, { cfg.untidy + 2, 0 })
  vim.wait(10000, function() return table.concat(vim.api.nvim_buf_get_lines(0, 0, -1, false), '\n') ~= untidy end, 20)
  result.range_formatted = vim.api.nvim_buf_get_lines(0, cfg.untidy, cfg.untidy + 2, false)

  -- Go to definition as a user does it: the client's own handler jumps.
  vim.api.nvim_win_set_cursor(0, { cfg.jump[1] + 1, cfg.jump[2] })
  local from = vim.api.nvim_buf_get_name(0)
  vim.lsp.buf.definition()
  vim.wait(10000, function() return vim.api.nvim_buf_get_name(0) ~= from end, 20)
  result.jump = { file = vim.api.nvim_buf_get_name(0), line = vim.api.nvim_win_get_cursor(0)[1] - 1,
                  text = vim.api.nvim_get_current_line() }

  vim.lsp.stop_client(client_id)
end

local ok, err = pcall(run)
if not ok then result.error = tostring(err) end
local ok_cfg, cfg = pcall(function()
  return vim.fn.json_decode(table.concat(vim.fn.readfile(vim.g.rcxc_config), "\n"))
end)
if ok_cfg then vim.fn.writefile({ vim.fn.json_encode(result) }, cfg.out) end
vim.cmd('qall!')
