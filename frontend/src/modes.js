// Highlighting of HMPL, PDL and GDL: small stream tokenizers (CodeMirror's StreamLanguage),
// keyword sets as the VS Code grammars of editors/vscode have them.
import { StreamLanguage } from "@codemirror/language";

const words = (text) => new Set(text.split(" "));

function cLike({ keywords, types, builtins, lineComment = "//", caseFold = false }) {
  const norm = (w) => (caseFold ? w.toLowerCase() : w);
  return {
    startState: () => ({ block: false }),
    token(stream, state) {
      if (state.block) {
        if (stream.skipTo("*/")) { stream.next(); stream.next(); state.block = false; }
        else stream.skipToEnd();
        return "comment";
      }
      if (stream.eatSpace()) return null;
      if (lineComment && stream.match(lineComment)) { stream.skipToEnd(); return "comment"; }
      if (stream.match("/*")) { state.block = true; return "comment"; }
      if (stream.sol() && stream.match(/^\s*#\s*\w+/)) return "meta";
      if (stream.match(/^"(?:[^"\\]|\\.)*"?/)) return "string";
      if (stream.match(/^'(?:[^'\\]|\\.)*'?/)) return "string";
      if (stream.match(/^(?:0x[0-9a-f]+|\d+\.?\d*(?:e[-+]?\d+)?|\.\d+)/i)) return "number";
      const w = stream.match(/^[A-Za-z_$][\w$]*/);
      if (w) {
        const word = norm(w[0]);
        if (keywords.has(word)) return "keyword";
        if (types.has(word)) return "typeName";
        if (builtins && builtins.has(word)) return "standard";
        return "variableName";
      }
      stream.next();
      return null;
    },
  };
}

export const hmpl = StreamLanguage.define(cLike({
  keywords: words("if else while do for switch case default break continue return goto Till sizeof const static extern volatile autorun"),
  types: words("void char short int long float double signed unsigned struct union enum typedef int8_t int16_t int32_t int64_t uint8_t uint16_t uint32_t uint64_t"),
}));

export const pdl = StreamLanguage.define(cLike({
  caseFold: true,
  keywords: words("halt wait sleep goto call ret exitproc loop do end if else while till proc kill tout lock unlock seton setoff toggle sttovar sizeof printl prints retprintl instate _ro _lp"),
  types: words("long float short"),
  builtins: words("max min abs unsign sign sin cos sqrt divi shift bitset bitclr bittog memcpy memset memmin memmax memsum"),
}));

const gdlKeywords = words("module end$module use procedure declare begin end$procedure if then else end$if while do end$while return of and or not");
const gdlConstants = words("on off present absent enabled disabled stopped running fault");

export const gdl = StreamLanguage.define({
  startState: () => ({ block: false }),
  token(stream, state) {
    if (state.block) {
      if (stream.skipTo("|")) { stream.next(); state.block = false; } else stream.skipToEnd();
      return "comment";
    }
    if (stream.eatSpace()) return null;
    if (stream.eat("|")) { state.block = true; return "comment"; }
    if (stream.match(/^'[^']*'?/) || stream.match(/^"[^"]*"?/)) return "string";
    if (stream.match(/^\d+\.?\d*(?:e[-+]?\d+)?/i)) return "number";
    const w = stream.match(/^[A-Za-z_][\w$]*/);
    if (w) {
      const word = w[0].toLowerCase();
      if (gdlKeywords.has(word)) return "keyword";
      if (gdlConstants.has(word)) return "atom";
      return "variableName";
    }
    stream.next();
    return null;
  },
});

export const modes = { hmpl, pdl, gdl };
