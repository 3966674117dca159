// The whole client: start `krlkit lsp` for KRL files and let vscode-languageclient speak LSP.
// Everything the editor shows (diagnostics, hovers, navigation, rename, formatting, the
// comparison with a backup) comes from the server; this file only says how to start it and
// asks which backup to compare with.
const fs = require('fs');
const path = require('path');
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

// Which krlkit to run: the `krlkit.path` setting when the user set one (a deliberate choice
// wins), else the binary bundled in a platform build of the extension (`server/`), else
// `krlkit` on the PATH.
function serverCommand(context, config) {
  const setting = config.get('path');
  if (setting) {
    return { command: setting, from: 'the krlkit.path setting' };
  }
  const exe = process.platform === 'win32' ? 'krlkit.exe' : 'krlkit';
  const bundled = path.join(context.extensionPath, 'server', exe);
  if (fs.existsSync(bundled)) {
    if (process.platform !== 'win32') {
      try {
        fs.accessSync(bundled, fs.constants.X_OK);
      } catch {
        fs.chmodSync(bundled, 0o755); // an unzip that dropped the mode bits
      }
    }
    return { command: bundled, from: 'the binary bundled with the extension' };
  }
  return { command: 'krlkit', from: 'the PATH' };
}

function activate(context) {
  const config = vscode.workspace.getConfiguration('krlkit');
  const output = vscode.window.createOutputChannel('krlkit');
  context.subscriptions.push(output);
  const { command, from } = serverCommand(context, config);
  output.appendLine(`krlkit: running ${command} lsp (${from})`);
  const serverOptions = { command, args: ['lsp'] };
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'krl' },
      { scheme: 'untitled', language: 'krl' },
    ],
    synchronize: {
      // Files changed outside the editor: KRL files, the config, the EKI channel XML.
      fileEvents: vscode.workspace.createFileSystemWatcher(
        '**/{*.src,*.dat,*.sub,*.SRC,*.DAT,*.SUB,*.xml,*.XML,.krlkit.toml,krlkit.toml}'
      ),
    },
    initializationOptions: { debounceMs: config.get('debounceMs') || 0 },
    outputChannel: output,
  };
  client = new LanguageClient('krlkit', 'krlkit', serverOptions, clientOptions);
  context.subscriptions.push(
    vscode.commands.registerCommand('krlkit.restart', () => client.restart()),
    vscode.commands.registerCommand('krlkit.compareWithBackup', () => compareWithBackup())
  );
  return client.start();
}

// "Compare with backup…": the server's `krlkit.diff` command (the same comparison as
// `krlkit diff BACKUP FOLDER`) on a backup folder or .zip the user picks; the report opens
// as a text document.
async function compareWithBackup() {
  const kind = await vscode.window.showQuickPick(
    [
      { label: 'A backup folder…', folder: true },
      { label: 'A backup .zip…', folder: false },
    ],
    { placeHolder: 'Compare the open folder with…' }
  );
  if (!kind) {
    return;
  }
  const picked = await vscode.window.showOpenDialog({
    canSelectFiles: !kind.folder,
    canSelectFolders: kind.folder,
    canSelectMany: false,
    filters: kind.folder ? undefined : { 'KUKA backup': ['zip', 'ZIP'] },
    openLabel: 'Compare',
  });
  if (!picked || picked.length === 0) {
    return;
  }
  try {
    const result = await client.sendRequest('workspace/executeCommand', {
      command: 'krlkit.diff',
      arguments: [picked[0].fsPath],
    });
    const doc = await vscode.workspace.openTextDocument({
      content: result.text,
      language: 'plaintext',
    });
    await vscode.window.showTextDocument(doc, { preview: false });
  } catch (e) {
    vscode.window.showErrorMessage(`krlkit: ${e.message || e}`);
  }
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
