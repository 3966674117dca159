// The whole client: start `krlkit lsp` for KRL files and let vscode-languageclient speak LSP.
// Everything the editor shows (diagnostics, hovers, navigation, rename, formatting) comes from
// the server; this file only says how to start it.
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration('krlkit');
  const command = config.get('path') || 'krlkit';
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
  };
  client = new LanguageClient('krlkit', 'krlkit', serverOptions, clientOptions);
  context.subscriptions.push(
    vscode.commands.registerCommand('krlkit.restart', () => client.restart())
  );
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
