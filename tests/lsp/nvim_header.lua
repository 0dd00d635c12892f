-- Drives `rcxc lsp` from headless Neovim with two buffers, for
-- tests/lsp/nvim_test.cpp: a header edited and left unsaved in one, the
-- program that includes it in the other. g:rcxc_config names a JSON file
-- with rcxc, dir (holding parts.nqh and main.nqc), stdlib_dir, out, and
-- typed (the header's lines as typed) and keys (typed in main.nqc). Written for Neovim 0.7 and later.
local result = {}
local function run()
  local cfg = vim.fn.json_decode(table.concat(vim.fn.readfile(vim.g.rcxc_config), "\n"))
  vim.o.hidden = true  -- the header stays modified while main.nqc is shown
  vim.cmd('cd ' .. vim.fn.fnameescape(cfg.dir))
  local client_id = vim.lsp.start_client({
    name = 'rcxc', cmd = { cfg.rcxc, 'lsp', '--stdlib-dir', cfg.stdlib_dir }, root_dir = cfg.dir,
  })
  assert(client_id, 'rcxc lsp did not start')
  vim.cmd('edit parts.nqh')
  vim.bo.filetype = 'nqc'
  vim.lsp.buf_attach_client(0, client_id)
  local header = vim.api.nvim_get_current_buf()
  vim.api.nvim_buf_set_lines(header, 0, -1, false, cfg.typed)
  vim.cmd('edit main.nqc')
  vim.bo.filetype = 'nqc'
  vim.lsp.buf_attach_client(0, client_id)
  local main = vim.api.nvim_get_current_buf()
  result.attached = vim.wait(10000, function() return #vim.diagnostic.get(main) > 0 end, 20)
  result.header_modified = vim.bo[header].modified
  result.diagnostics = {}
  for _, d in ipairs(vim.diagnostic.get(main)) do
    table.insert(result.diagnostics, { lnum = d.lnum, col = d.col, message = d.message })
  end
  -- Go to definition on `turn` (line 5, the name the header gained).
  vim.api.nvim_win_set_cursor(0, { 5, 3 })
  vim.lsp.buf.definition()
  vim.wait(10000, function() return vim.api.nvim_get_current_buf() ~= main end, 20)
  result.jump = { file = vim.api.nvim_buf_get_name(0), line = vim.api.nvim_win_get_cursor(0)[1] - 1,
                  text = vim.api.nvim_get_current_line(), same_buffer = vim.api.nvim_get_current_buf() == header }
  -- Typed in insert mode at the end of line 6 of main.nqc: a comment of
  -- wide letters, a new line with two undeclared names. The client sends
  -- each change as a range in UTF-16 units.
  vim.cmd('buffer ' .. main)
  vim.api.nvim_win_set_cursor(0, { 6, 0 })
  vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes(cfg.keys, true, false, true), 'xt', false)
  vim.wait(10000, function()
    for _, d in ipairs(vim.diagnostic.get(main)) do
      if d.message:find('zip', 1, true) then return true end
    end
    return false
  end, 20)
  result.typed = vim.api.nvim_buf_get_lines(main, 0, -1, false)
  result.after_typing = {}
  for _, d in ipairs(vim.diagnostic.get(main)) do
    table.insert(result.after_typing, { lnum = d.lnum, col = d.col, message = d.message })
  end
  table.sort(result.after_typing, function(a, b) return a.lnum < b.lnum or (a.lnum == b.lnum and a.col < b.col) end)
  vim.lsp.stop_client(client_id)
end

local ok, err = pcall(run)
if not ok then result.error = tostring(err) end
local ok_cfg, cfg = pcall(function()
  return vim.fn.json_decode(table.concat(vim.fn.readfile(vim.g.rcxc_config), "\n"))
end)
if ok_cfg then vim.fn.writefile({ vim.fn.json_encode(result) }, cfg.out) end
vim.cmd('qall!')
