-- Run by test/run.sh: with require("qcsg").setup(), opens a .qcsg file that uses an undefined
-- variable, waits for the diagnostic from `qcsg lsp` (code and position), then hovers over a
-- variable and checks the text. Exits non-zero on any failure.
local bin = assert(os.getenv("QCSG_BIN"), "QCSG_BIN is not set")
local dir = assert(os.getenv("QCSG_TEST_DIR"), "QCSG_TEST_DIR is not set")
local timeout_ms = 30000

local function check(cond, msg)
  if not cond then
    error(msg, 2)
  end
end

-- The ids of the clients attached to `buf` (or of all clients); Neovim 0.7 to 0.11+.
local function client_ids(buf)
  local ids = {}
  if vim.lsp.get_clients then
    for _, client in ipairs(vim.lsp.get_clients(buf and { bufnr = buf } or nil)) do
      table.insert(ids, client.id)
    end
  else
    for id, _ in pairs(buf and vim.lsp.buf_get_clients(buf) or vim.lsp.get_active_clients()) do
      table.insert(ids, id)
    end
  end
  return ids
end

local function run()
  local lines = {
    "/// Width of the plate.",
    "width = 20;",
    "cube([width, 10, 2]);",
    "translate([0, 0, missing]) sphere(1);",
  }
  local file = dir .. "/plate.qcsg"
  vim.fn.writefile(lines, file)

  require("qcsg").setup({ cmd = { bin, "lsp" } })
  vim.cmd("edit " .. vim.fn.fnameescape(file))
  local buf = vim.api.nvim_get_current_buf()
  check(vim.bo[buf].filetype == "qcsg", "filetype is '" .. vim.bo[buf].filetype .. "', not qcsg")
  check(vim.b[buf].current_syntax == "qcsg", "syntax/qcsg.vim was not loaded")

  -- The server attaches and reports the undefined name (E0101) at `missing`: line 3, column 17
  -- (both 0-based).
  local found
  vim.wait(timeout_ms, function()
    for _, d in ipairs(vim.diagnostic.get(buf)) do
      if d.code == "E0101" then
        found = d
        return true
      end
    end
    return false
  end, 50)
  local clients = client_ids(buf)
  check(#clients > 0, "no language server attached to the buffer")
  if not found then
    local got = {}
    for _, d in ipairs(vim.diagnostic.get(buf)) do
      table.insert(got, string.format("%s@%d:%d %s", tostring(d.code), d.lnum, d.col, d.message))
    end
    error("no E0101 diagnostic within " .. timeout_ms .. " ms; got: " .. table.concat(got, "; "))
  end
  check(found.lnum == 3 and found.col == 17 and found.end_col == 24, string.format(
    "E0101 at %d:%d-%d, expected 3:17-24", found.lnum, found.col, found.end_col))
  check(found.severity == vim.diagnostic.severity.ERROR, "E0101 is not an error")
  check(found.message:find("missing", 1, true), "message does not name `missing`: " .. found.message)

  -- Hover over `width` in `cube([width, ...])`: its definition and doc comment.
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    position = { line = 2, character = 7 },
  }
  local responses = vim.lsp.buf_request_sync(buf, "textDocument/hover", params, timeout_ms)
  check(responses, "no hover response")
  local text
  for _, response in pairs(responses) do
    check(not response.err, "hover failed: " .. vim.inspect(response.err))
    if response.result and response.result.contents then
      local contents = response.result.contents
      text = type(contents) == "string" and contents or contents.value
    end
  end
  check(text, "empty hover")
  check(text:find("width = 20", 1, true), "hover lacks `width = 20`: " .. text)
  check(text:find("Width of the plate.", 1, true), "hover lacks the doc comment: " .. text)

  -- Shut the server down cleanly.
  for _, id in ipairs(clients) do
    vim.lsp.stop_client(id)
  end
  vim.wait(5000, function()
    return #client_ids(nil) == 0
  end, 50)
end

local ok, err = xpcall(run, debug.traceback)
if ok then
  io.stdout:write("\nneovim lsp test: ok\n")
  vim.cmd("qall!")
else
  io.stderr:write("\nneovim lsp test: FAIL: " .. tostring(err) .. "\n")
  vim.cmd("cquit 1")
end
