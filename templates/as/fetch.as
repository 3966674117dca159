{% extends "as/program.as" %}
{% block init %}
{%- for o in r.zero_outs %}
  {{ o }} = 0
{%- endfor %}
{% endblock %}
{% block body %}
  ; Repeats the request until the server reports all sent; see mm_fetch.
  .st = 0
  CALL mm_fetch({{ r.cmd }},{{ r.ok }},{{ r.fetch_args }})
{% endblock %}
