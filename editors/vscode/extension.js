// The motionvm extension: starts `motionvm lsp` for .hmpl/.pdl/.gdl files and
// `motionvm debug` for launch configurations of type "motionvm".
"use strict";

const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;

function command() {
  return vscode.workspace.getConfiguration("motionvm").get("path") || "motionvm";
}

function activate(context) {
  const run = { command: command(), args: ["lsp"], transport: TransportKind.stdio };
  client = new LanguageClient(
    "motionvm",
    "motionvm",
    { run, debug: run },
    {
      documentSelector: [
        { scheme: "file", language: "hmpl" },
        { scheme: "file", language: "pdl" },
        { scheme: "file", language: "gdl" },
        { scheme: "untitled", language: "hmpl" },
        { scheme: "untitled", language: "pdl" },
        { scheme: "untitled", language: "gdl" },
      ],
    }
  );
  client.start();
  context.subscriptions.push(
    vscode.debug.registerDebugAdapterDescriptorFactory("motionvm", {
      createDebugAdapterDescriptor(session) {
        const cwd = session.configuration.cwd;
        return new vscode.DebugAdapterExecutable(command(), ["debug"], cwd ? { cwd } : {});
      },
    })
  );
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
