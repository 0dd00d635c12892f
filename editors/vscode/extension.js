// Starts `rcxc lsp` for NQC files, and `rcxc debug` for launch
// configurations of type "rcxc" (docs/editors.md). Needs the
// vscode-languageclient package: `npm install` in this folder.
const path = require('path');
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');

let client;

// The include folders of the settings as rcxc reads them. VS Code does not
// expand `${workspaceFolder}` in an extension's settings, and the server's
// current folder is not the workspace: both are resolved here against the
// first workspace folder (a relative folder without a workspace is left as
// it is).
function includeDirs(config) {
  const folders = vscode.workspace.workspaceFolders || [];
  const root = folders.length > 0 ? folders[0].uri.fsPath : undefined;
  return config.get('includeDirs', []).map((dir) => {
    if (root === undefined) return dir;
    const expanded = dir.split('${workspaceFolder}').join(root);
    return path.isAbsolute(expanded) ? expanded : path.join(root, expanded);
  });
}

function startClient() {
  const config = vscode.workspace.getConfiguration('rcxc');
  const args = ['lsp'];
  for (const dir of includeDirs(config)) args.push('-I', dir);
  const server = { command: config.get('path', 'rcxc'), args, transport: TransportKind.stdio };
  client = new LanguageClient('rcxc', 'NQC (rcxc)', server, {
    documentSelector: [{ scheme: 'file', language: 'nqc' }, { scheme: 'untitled', language: 'nqc' }],
  });
  return client.start();
}

function activate(context) {
  // The server reads its options when it starts: a changed setting
  // (rcxc.path, rcxc.includeDirs) restarts it rather than waiting for the
  // next window.
  context.subscriptions.push(vscode.workspace.onDidChangeConfiguration(async (event) => {
    if (!event.affectsConfiguration('rcxc.path') && !event.affectsConfiguration('rcxc.includeDirs')) return;
    if (client) await client.stop();
    await startClient();
  }));
  context.subscriptions.push({ dispose: () => (client ? client.stop() : undefined) });
  // The debugger is `rcxc debug` on standard input and output, the same
  // executable as the language server (rcxc.path).
  context.subscriptions.push(vscode.debug.registerDebugAdapterDescriptorFactory('rcxc', {
    createDebugAdapterDescriptor: () =>
      new vscode.DebugAdapterExecutable(vscode.workspace.getConfiguration('rcxc').get('path', 'rcxc'), ['debug']),
  }));
  return startClient();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
