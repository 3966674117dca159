{% extends "py/mm/method.py" %}
{%- block body %}
        status, f = self._exchange({{ m.cmd }}, [{{ m.tx }}])
        if status == {{ m.ok }}:
            if len(f) != {{ m.lay.head + v.do_list_len }}:
                status = self.BAD_REPLY
            else:
                for i in range(1, {{ v.do_list_len + 1 }}):
                    self.do_port[i] = int(f[{{ m.lay.head - 1 }} + i])
                self._do_valid = True
        self.last_status = status
{%- endblock %}
