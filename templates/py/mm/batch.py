{% extends "py/mm/method.py" %}
{%- block body %}
        # A failure leaves the stored points alone and reports last_data = 1, so a
        # "while last_data == 0" loop ends.
        last_data, pos_num, vispos_num = 1, 0, 0
{%- if m.has_bad %}
        if {{ m.bad }}:
            status = self.BAD_ARGUMENT
        else:
{%- else %}
        if True:
{%- endif %}
            status, f = self._exchange({{ m.cmd }}, [{{ m.tx }}])
            if status == {{ m.ok }}:
                err = self._store_batch(f, {{ m.kind }}, {{ m.lay.head }}, {{ m.lay.record }}, {{ m.lay.count_at }})
                if err:
                    status = err
                else:
                    self._pt_status = status
                    last_data, pos_num = int(f[{{ m.lay.all_sent_at }}]), len(self._points)
{%- if m.lay.vispos_at > 0 %}
                    vispos_num = int(f[{{ m.lay.vispos_at }}])
{%- endif %}
        self.last_status = status
        return {{ m.ret }}
{%- endblock %}
