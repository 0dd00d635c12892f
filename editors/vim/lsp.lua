-- Neovim: rcxc's language server for NQC buffers (docs/editors.md).
-- Put this file's contents in your init.lua (or :luafile it). Neovim 0.8 and
-- later have vim.lsp.start; 0.7 (Debian 12) gets start_client below.
vim.api.nvim_create_autocmd('FileType', {
  pattern = 'nqc',
  callback = function(args)
    local config = {
      name = 'rcxc',
      cmd = { 'rcxc', 'lsp' },  -- add '-I', 'DIR' for your include folders
      root_dir = vim.fs and vim.fs.dirname(args.file) or vim.fn.fnamemodify(args.file, ':p:h'),
    }
    if vim.lsp.start then
      vim.lsp.start(config)
    else
      local id = vim.lsp.start_client(config)
      if id then vim.lsp.buf_attach_client(args.buf, id) end
    end
  end,
})
