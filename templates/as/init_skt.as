{% extends "as/program.as" %}
{% block body %}
  ; A new address replaces the old connection.
  CALL mm_close
  mm_ip[1] = {{ r.arg(".ip1") }}
  mm_ip[2] = {{ r.arg(".ip2") }}
  mm_ip[3] = {{ r.arg(".ip3") }}
  mm_ip[4] = {{ r.arg(".ip4") }}
  mm_port = {{ r.arg(".port") }}
  mm_skt_ok = 1
  ; When the vision PC is not up yet, every later mm_ call tries again.
  .st = 0
  CALL mm_connect(.st)
{% endblock %}
