"""CI only: drive `krlkit.exe lsp` under Wine over stdio: initialize, initialized, didOpen of a
KRL file (by its Windows file URI), then expect the server's capabilities and the file's
diagnostics, shutdown and exit."""
import json, subprocess, sys

def frame(msg):
    body = json.dumps(msg).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body

def read(stream):
    length = None
    while True:
        line = stream.readline()
        if not line:
            raise SystemExit("lsp: the server closed stdout")
        line = line.strip()
        if not line:
            break
        if line.lower().startswith(b"content-length:"):
            length = int(line.split(b":")[1])
    return json.loads(stream.read(length))

cmd, uri, text = sys.argv[1:-2], sys.argv[-2], sys.argv[-1]
p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE)
send = lambda m: (p.stdin.write(frame(m)), p.stdin.flush())
send({"jsonrpc": "2.0", "id": 1, "method": "initialize",
      "params": {"processId": None, "rootUri": None, "capabilities": {}}})
init = read(p.stdout)
assert "capabilities" in init.get("result", {}), init
send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
    "uri": uri, "languageId": "krl", "version": 1, "text": open(text, newline="").read()}}})
while True:
    m = read(p.stdout)
    if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["uri"].lower() == uri.lower():
        break
diags = m["params"]["diagnostics"]
send({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
while read(p.stdout).get("id") != 2:
    pass
send({"jsonrpc": "2.0", "method": "exit"})
sys.exit(print(f"lsp: initialize answered, {len(diags)} diagnostics for {uri}") or p.wait(timeout=30))
