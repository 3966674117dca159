{% extends "as/program.as" %}
{% block body %}
  .st = 0
  IF mm_do_ok <> 1 THEN
    .st = {{ p.codes.wrong_data_kind }}
  ELSE
    FOR .i = 1 TO {{ p.do_list_len }}
      .s = mm_do_list[.i]
      IF (.s >= 1) AND (.s <= {{ p.do_value_max }}) THEN
        SIGNAL .s
      END
    END
  END
{% endblock %}
