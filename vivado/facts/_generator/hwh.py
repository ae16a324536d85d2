import xml.etree.ElementTree as ET
def parse_hwh(path):
    root = ET.parse(path).getroot()
    sysinfo = root.find('SYSTEMINFO').attrib
    mods = []
    for m in root.iter('MODULE'):
        a = m.attrib
        params = []
        pe = m.find('PARAMETERS')
        if pe is not None:
            params = [(p.get('NAME'), p.get('VALUE')) for p in pe.findall('PARAMETER')]
        ports = []
        po = m.find('PORTS')
        if po is not None:
            for p in po.findall('PORT'):
                ports.append(dict(name=p.get('NAME'), dir=p.get('DIR'), left=p.get('LEFT'), right=p.get('RIGHT'),
                                  sigis=p.get('SIGIS'), connected=p.find('CONNECTIONS') is not None,
                                  conns=[(c.get('INSTANCE'), c.get('PORT')) for c in p.iter('CONNECTION')]))
        bifs = []
        bi = m.find('BUSINTERFACES')
        if bi is not None:
            for b in bi.findall('BUSINTERFACE'):
                bifs.append(dict(name=b.get('NAME'), type=b.get('TYPE'), vlnv=b.get('VLNV'), busname=b.get('BUSNAME'),
                                 portmaps=[(pm.get('LOGICAL'), pm.get('PHYSICAL')) for pm in b.iter('PORTMAP')]))
        mods.append(dict(corerev=a.get('COREREVISION'), hwversion=a.get('HWVERSION'), instance=a.get('INSTANCE'), vlnv=a.get('VLNV'), modtype=a.get('MODTYPE'), params=params, ports=ports, bifs=bifs))
    return root.attrib, sysinfo, mods
