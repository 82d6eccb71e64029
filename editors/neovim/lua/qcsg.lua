-- Starts the qcsg language server (`qcsg lsp`) for qcsg and OpenSCAD buffers.
--
--   require("qcsg").setup()                                  -- `qcsg` on PATH
--   require("qcsg").setup({ cmd = { "/path/to/qcsg", "lsp" } })
--
-- Works on Neovim 0.7 (vim.lsp.start_client) and later (vim.lsp.start); one server per root.
local M = {}

M.defaults = {
  cmd = { "qcsg", "lsp" },
  filetypes = { "qcsg", "openscad" },
  -- The first ancestor holding one of these is the workspace root (else the file's directory).
  root_markers = { ".git" },
  -- Passed on to the client (on_attach, capabilities, settings, ...).
  client = {},
}

local clients = {} -- root directory -> client id (Neovim 0.7)

local function root_dir(bufnr, markers)
  local file = vim.api.nvim_buf_get_name(bufnr)
  local dir = file ~= "" and vim.fn.fnamemodify(file, ":p:h") or vim.fn.getcwd()
  for _, marker in ipairs(markers) do
    local found = vim.fn.finddir(marker, dir .. ";")
    if found == "" then
      found = vim.fn.findfile(marker, dir .. ";")
    end
    if found ~= "" then
      -- The marker's own path (without a trailing slash), then the directory holding it.
      local marker_path = (vim.fn.fnamemodify(found, ":p"):gsub("/$", ""))
      return vim.fn.fnamemodify(marker_path, ":h")
    end
  end
  return dir
end

--- Starts (or reuses) the server for `bufnr` and attaches it; returns the client id.
function M.attach(bufnr, opts)
  opts = opts or M.options or M.defaults
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  local root = root_dir(bufnr, opts.root_markers)
  local config = vim.tbl_extend("force", {
    name = "qcsg",
    cmd = opts.cmd,
    root_dir = root,
  }, opts.client)
  if vim.lsp.start then
    return vim.lsp.start(config, { bufnr = bufnr })
  end
  local id = clients[root]
  if not id or not vim.lsp.get_client_by_id(id) or vim.lsp.client_is_stopped(id) then
    id = vim.lsp.start_client(config)
    clients[root] = id
  end
  if id then
    vim.lsp.buf_attach_client(bufnr, id)
  end
  return id
end

local views = {} -- file -> job id of its `qcsg view`

--- Runs `qcsg view` (the live preview in the browser) for the current buffer's file, saved
--- first; a second call for the same file stops the server. `cmd[1]` of the options is the
--- `qcsg` binary.
function M.view()
  local file = vim.api.nvim_buf_get_name(0)
  if file == "" then
    vim.notify("qcsg: the buffer has no file to preview", vim.log.levels.WARN)
    return
  end
  if views[file] then
    vim.fn.jobstop(views[file])
    views[file] = nil
    vim.notify("qcsg: preview stopped")
    return
  end
  if vim.bo.modified then
    vim.cmd("write")
  end
  local qcsg = ((M.options or M.defaults).cmd or { "qcsg" })[1]
  local job = vim.fn.jobstart({ qcsg, "view", file }, {
    on_stdout = function(_, lines)
      for _, line in ipairs(lines) do
        if line:find("http://", 1, true) then
          vim.schedule(function()
            vim.notify(line)
          end)
        end
      end
    end,
    on_exit = function()
      views[file] = nil
    end,
  })
  if job <= 0 then
    vim.notify("qcsg: cannot run " .. qcsg .. " view", vim.log.levels.ERROR)
    return
  end
  views[file] = job
end

--- Registers the filetypes' autocommand and `:QcsgView`; call once from your config.
function M.setup(opts)
  M.options = vim.tbl_deep_extend("force", {}, M.defaults, opts or {})
  vim.api.nvim_create_user_command("QcsgView", M.view, {
    desc = "qcsg: live preview of this file in the browser (again: stop it)",
  })
  local group = vim.api.nvim_create_augroup("qcsg_lsp", { clear = true })
  vim.api.nvim_create_autocmd("FileType", {
    group = group,
    pattern = M.options.filetypes,
    callback = function(args)
      M.attach(args.buf, M.options)
    end,
  })
  -- Buffers that were already open when setup ran.
  for _, buf in ipairs(vim.api.nvim_list_bufs()) do
    if vim.api.nvim_buf_is_loaded(buf) and vim.tbl_contains(M.options.filetypes, vim.bo[buf].filetype) then
      M.attach(buf, M.options)
    end
  end
end

return M
