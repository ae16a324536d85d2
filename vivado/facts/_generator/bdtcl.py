import re
def tcl_words(s):
    """minimal Tcl word splitter handling {..} and [..] and "..", for one command string"""
    words = []; i = 0; n = len(s)
    while i < n:
        while i < n and s[i] in ' \t': i += 1
        if i >= n: break
        if s[i] == '{':
            d = 0; j = i
            while j < n:
                if s[j] == '{': d += 1
                elif s[j] == '}':
                    d -= 1
                    if d == 0: break
                j += 1
            words.append(s[i + 1:j]); i = j + 1
        elif s[i] == '[':
            d = 0; j = i
            while j < n:
                if s[j] == '[': d += 1
                elif s[j] == ']':
                    d -= 1
                    if d == 0: break
                j += 1
            words.append(s[i:j + 1]); i = j + 1
        elif s[i] == '"':
            j = s.index('"', i + 1); words.append(s[i + 1:j]); i = j + 1
        else:
            j = i
            while j < n and s[j] not in ' \t': j += 1
            words.append(s[i:j]); i = j
    return words
def commands(text):
    text = re.sub(r'\\\n\s*', ' ', text)  # backslash-newline -> space (Tcl semantics)
    return [l.strip() for l in text.split('\n') if l.strip() and not l.strip().startswith('#')]
def parse_bd_tcl(text):
    cells = {}   # var/name -> vlnv
    cfg = {}     # cell -> {prop: value}
    pins = []    # (cell, pin, kind)  kind in pin/intf_pin
    ports = []   # external ports
    for c in commands(text):
        m = re.match(r'set\s+(\S+)\s+\[\s*create_bd_cell\s+-type\s+ip\s+-vlnv\s+(\S+)\s+(\S+)\s*\]', c)
        if m:
            cells[m.group(3)] = m.group(2); continue
        m = re.match(r'create_bd_cell\s+-type\s+ip\s+-vlnv\s+(\S+)\s+(\S+)', c)
        if m:
            cells[m.group(2).split('/')[-1]] = m.group(1); continue
        if c.startswith('set_property'):
            w = tcl_words(c)
            target = w[-1]
            tgt = target.lstrip('$')
            if tgt.startswith('[get_bd_cells'):
                tgt = tcl_words(tgt[1:-1])[-1].split('/')[-1]
            if w[1] == '-dict':
                lst = w[2]
                if lst.startswith('[') : lst = lst[1:-1]
                lw = tcl_words(lst)
                if lw and lw[0] == 'list': lw = lw[1:]
                for k in range(0, len(lw) - 1, 2):
                    if lw[k].startswith('CONFIG.'):
                        cfg.setdefault(tgt, {})[lw[k][7:]] = lw[k + 1]
            elif w[1].startswith('CONFIG.') and len(w) >= 4:
                cfg.setdefault(tgt, {})[w[1][7:]] = w[2]
            continue
        if c.startswith('connect_bd_net') or c.startswith('connect_bd_intf_net'):
            kind = 'intf_pin' if 'intf' in c.split()[0] else 'pin'
            for m in re.finditer(r'\[get_bd_(intf_pins|pins)\s+([^\]]+)\]', c):
                for p in m.group(2).split():
                    p = p.strip('{}')
                    if '/' in p:
                        cell, pin = p.rsplit('/', 1)
                        pins.append((cell.split('/')[-1], pin, 'intf_pin' if m.group(1) == 'intf_pins' else 'pin'))
    return cells, cfg, pins
