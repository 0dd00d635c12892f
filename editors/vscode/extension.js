// Starts `rcxc lsp` for NQC files (docs/editors.md). Needs the
// vscode-languageclient package: `npm install` in this folder.
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration('rcxc');
  const args = ['lsp'];
  for (const dir of config.get('includeDirs', [])) args.push('-I', dir);
  const server = { command: config.get('path', 'rcxc'), args, transport: TransportKind.stdio };
  client = new LanguageClient('rcxc', 'NQC (rcxc)', server, {
    documentSelector: [{ scheme: 'file', language: 'nqc' }, { scheme: 'untitled', language: 'nqc' }],
  });
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
